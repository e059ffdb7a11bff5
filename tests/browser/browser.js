// What the browser tests share: Debian's Chromium, headless, trusting the dashboard's key by
// its pin as a cell's browsers would trust the cell CA; check(), which ends the test at the
// first failed expectation; and logIn(), a cell user's login with the password `cell up`
// generated in its work directory; and runDemonstrator(), a demonstrator's process run from
// the page (demonstrator_test.sh gives the cell's page, key pin and work directory).
"use strict";
const { chromium } = require("playwright-core");
const fs = require("fs");
const path = require("path");

function launch(spki) {
  return chromium.launch({
    executablePath: "/usr/bin/chromium",
    args: ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
           "--disable-component-update", "--disable-sync", "--no-first-run",
           "--ignore-certificate-errors-spki-list=" + spki],
  });
}

function check(condition, what) {
  if (!condition) throw new Error("expected: " + what);
  console.log("ok  " + what);
}

// Logs `user` in on the page, with the password in `<workDir>/<user>.pw`, and waits for the
// cell's view.
async function logIn(page, workDir, user, wait) {
  await page.waitForSelector("#login:not([hidden])", wait);
  await page.fill("#login-user", user);
  await page.fill("#login-password", fs.readFileSync(path.join(workDir, user + ".pw"), "utf8").trim());
  await page.click("#login button[type=submit]");
  await page.waitForSelector("#cell:not([hidden])", wait);
}

// One of the paper's demonstrators: the Operator logs in, `before(page, wait)` checks the
// picture of the cell as it stands, the Operator runs the process `processIri` (whose steps
// must name `stepType`) to its end, `after(page, wait)` checks the picture of what it did,
// no tool may be left on the flange, and `shot` (a file name) receives the picture. Every wait
// is bounded; the first failed expectation ends the test with exit code 1.
function runDemonstrator({ processIri, stepType, before, after, shot }) {
  const wait = { timeout: 60000 };
  const run = { timeout: 240000 };  // the whole process, on a slow machine
  (async () => {
    const browser = await launch(process.env.DASHBOARD_SPKI);
    try {
      const page = await browser.newPage({ viewport: { width: 1200, height: 900 } });
      await page.goto(process.env.DASHBOARD_URL);
      await logIn(page, process.env.CELL_WORK_DIR, "operator", wait);
      await before(page, wait);

      const row = `#processes tr[data-process="${processIri}"]`;
      await page.waitForSelector(row + " button[data-action=start]:not([disabled])", wait);
      const steps = await page.textContent(row + " td:nth-child(2)");
      check(steps.includes("2 " + stepType), "the KB's process has " + stepType + " steps (" + steps + ")");
      await page.click(row + " button[data-action=start]");
      await page.waitForSelector(row + ' .result[data-status="Good"]', wait);
      await page.waitForSelector(row + ' .progress[data-state="completed"]', run);
      check(true, "the run completed");
      await after(page, wait);
      await page.waitForSelector('#scene g.flange[data-tool=""]', wait);
      check(true, "and no tool on the flange");
      const shots = process.env.SCREENSHOT_DIR;
      if (shots) await page.screenshot({ path: path.join(shots, shot), fullPage: true });
    } finally {
      await browser.close();
    }
  })().catch((e) => {
    console.error("FAILED: " + e.message);
    process.exit(1);
  });
}

module.exports = { launch, check, logIn, runDemonstrator };
