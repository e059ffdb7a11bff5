// The fuse-box demonstrator run from the dashboard, in headless Chromium (demonstrator_test.sh
// brings up examples/cells/fuse-box.toml with `skillcell cell up`): the fuse box is drawn with
// its three slots empty, the Operator runs the cell's process to its end, and the picture then
// shows each fuse in its slot.
"use strict";
const { check, runDemonstrator } = require("./browser");

const box = "#scene g.fuse-box";
runDemonstrator({
  processIri: "http://skillcell.dev/demo/fuse-box#fusesIntoTheBox",
  stepType: "InsertFuseSkillType",
  shot: "dashboard-fuse-box.png",
  before: async (page, wait) => {
    await page.waitForSelector(box + '[data-seated="F1: F2: F3:"]', wait);
    check(true, "the picture shows the fuse box, its slots F1, F2, F3 empty");
    await page.waitForSelector('#scene g[data-object="fuse10A"][data-x="0.450"][data-y="-0.050"]', wait);
    check(true, "fuse10A stands in its tray at (0.45, -0.05)");
  },
  after: async (page, wait) => {
    await page.waitForSelector(box + '[data-seated="F1:fuse10A F2:fuse15A F3:fuse20A"]', wait);
    const label = await page.textContent(box + " text");
    check(label === "fuse box: F1 fuse10A, F2 fuse15A, F3 fuse20A",
          "the picture shows each fuse in its slot (" + label + ")");
    check(await page.locator('#scene g[data-object="fuse10A"]').count() === 0,
          "a seated fuse is drawn as its slot, filled");
  },
});
