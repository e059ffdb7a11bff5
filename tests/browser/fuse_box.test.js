// The fuse-box demonstrator run from the dashboard, in headless Chromium (demonstrator_test.sh
// brings up examples/cells/fuse-box.toml with `skillcell cell up`): the fuse box is drawn with
// its three slots empty, the Operator runs the cell's process to its end, and the picture then
// shows each fuse in its slot. Every wait is bounded; the first failed expectation ends the
// test with exit code 1.
"use strict";
const { launch, check, logIn } = require("./browser");
const path = require("path");

const url = process.env.DASHBOARD_URL;
const spki = process.env.DASHBOARD_SPKI;
const work = process.env.CELL_WORK_DIR;
const shots = process.env.SCREENSHOT_DIR;
const wait = { timeout: 60000 };
const run = { timeout: 240000 };  // the whole process, on a slow machine
const processIri = "http://skillcell.dev/demo/fuse-box#fusesIntoTheBox";

(async () => {
  const browser = await launch(spki);
  try {
    const page = await browser.newPage({ viewport: { width: 1200, height: 900 } });
    await page.goto(url);
    await logIn(page, work, "operator", wait);

    const box = "#scene g.fuse-box";
    await page.waitForSelector(box + '[data-seated="F1: F2: F3:"]', wait);
    check(true, "the picture shows the fuse box, its slots F1, F2, F3 empty");
    await page.waitForSelector('#scene g[data-object="fuse10A"][data-x="0.450"][data-y="-0.050"]', wait);
    check(true, "fuse10A stands in its tray at (0.45, -0.05)");

    const row = `#processes tr[data-process="${processIri}"]`;
    await page.waitForSelector(row + " button[data-action=start]:not([disabled])", wait);
    const steps = await page.textContent(row + " td:nth-child(2)");
    check(steps.includes("2 InsertFuseSkillType"), "the KB's process inserts fuses (" + steps + ")");
    await page.click(row + " button[data-action=start]");
    await page.waitForSelector(row + ' .result[data-status="Good"]', wait);
    await page.waitForSelector(row + ' .progress[data-state="completed"]', run);
    check(true, "the run completed");
    await page.waitForSelector(box + '[data-seated="F1:fuse10A F2:fuse15A F3:fuse20A"]', wait);
    const label = await page.textContent(box + " text");
    check(label === "fuse box: F1 fuse10A, F2 fuse15A, F3 fuse20A",
          "the picture shows each fuse in its slot (" + label + ")");
    check(await page.locator('#scene g[data-object="fuse10A"]').count() === 0,
          "a seated fuse is drawn as its slot, filled");
    await page.waitForSelector('#scene g.flange[data-tool=""]', wait);
    check(true, "and no tool on the flange");
    if (shots) await page.screenshot({ path: path.join(shots, "dashboard-fuse-box.png"), fullPage: true });
  } finally {
    await browser.close();
  }
})().catch((e) => {
  console.error("FAILED: " + e.message);
  process.exit(1);
});
