// The DIN-rail demonstrator run from the dashboard, in headless Chromium (demonstrator_test.sh
// brings up examples/cells/din-rail.toml with `skillcell cell up`): the rail is drawn empty,
// the Operator runs the cell's process to its end, and the picture then shows tb1, tb2 and
// tb3 on rail1 side by side at their width. Every wait is bounded; the first failed
// expectation ends the test with exit code 1.
"use strict";
const { launch, check, logIn } = require("./browser");
const path = require("path");

const url = process.env.DASHBOARD_URL;
const spki = process.env.DASHBOARD_SPKI;
const work = process.env.CELL_WORK_DIR;
const shots = process.env.SCREENSHOT_DIR;
const wait = { timeout: 60000 };
const run = { timeout: 240000 };  // the whole process, on a slow machine
const processIri = "http://skillcell.dev/demo/din-rail#terminalBlocksOnARail";

(async () => {
  const browser = await launch(spki);
  try {
    const page = await browser.newPage({ viewport: { width: 1200, height: 900 } });
    await page.goto(url);
    await logIn(page, work, "operator", wait);

    const rail = '#scene g.rail[data-rail="rail1"]';
    await page.waitForSelector(rail + '[data-blocks=""]', wait);
    check(true, "the picture shows rail1, empty");
    await page.waitForSelector('#scene g[data-object="tb1"][data-x="0.450"][data-y="0.000"]', wait);
    check(true, "tb1 stands in its tray at (0.45, 0)");

    const row = `#processes tr[data-process="${processIri}"]`;
    await page.waitForSelector(row + " button[data-action=start]:not([disabled])", wait);
    const steps = await page.textContent(row + " td:nth-child(2)");
    check(steps.includes("2 PlaceTerminalBlockSkillType"), "the KB's process places terminal blocks (" + steps + ")");
    await page.click(row + " button[data-action=start]");
    await page.waitForSelector(row + ' .result[data-status="Good"]', wait);
    await page.waitForSelector(row + ' .progress[data-state="completed"]', run);
    check(true, "the run completed");
    await page.waitForSelector(rail + '[data-blocks="tb1@2.6 tb2@7.8 tb3@13.0"]', wait);
    const label = await page.textContent(rail + " text");
    check(label === "rail1: tb1 at 2.6 mm, tb2 at 7.8 mm, tb3 at 13.0 mm",
          "the picture shows the three blocks side by side on rail1 (" + label + ")");
    await page.waitForSelector('#scene g.flange[data-tool=""]', wait);
    check(true, "and no tool on the flange");
    if (shots) await page.screenshot({ path: path.join(shots, "dashboard-din-rail.png"), fullPage: true });
  } finally {
    await browser.close();
  }
})().catch((e) => {
  console.error("FAILED: " + e.message);
  process.exit(1);
});
