// The DIN-rail demonstrator run from the dashboard, in headless Chromium (demonstrator_test.sh
// brings up examples/cells/din-rail.toml with `skillcell cell up`): the rail is drawn empty,
// the Operator runs the cell's process to its end, and the picture then shows tb1, tb2 and
// tb3 on rail1 side by side at their width.
"use strict";
const { check, runDemonstrator } = require("./browser");

const rail = '#scene g.rail[data-rail="rail1"]';
runDemonstrator({
  processIri: "http://skillcell.dev/demo/din-rail#terminalBlocksOnARail",
  stepType: "PlaceTerminalBlockSkillType",
  shot: "dashboard-din-rail.png",
  before: async (page, wait) => {
    await page.waitForSelector(rail + '[data-blocks=""]', wait);
    check(true, "the picture shows rail1, empty");
    await page.waitForSelector('#scene g[data-object="tb1"][data-x="0.450"][data-y="0.000"]', wait);
    check(true, "tb1 stands in its tray at (0.45, 0)");
  },
  after: async (page, wait) => {
    await page.waitForSelector(rail + '[data-blocks="tb1@2.6 tb2@7.8 tb3@13.0"]', wait);
    const label = await page.textContent(rail + " text");
    check(label === "rail1: tb1 at 2.6 mm, tb2 at 7.8 mm, tb3 at 13.0 mm",
          "the picture shows the three blocks side by side on rail1 (" + label + ")");
  },
});
