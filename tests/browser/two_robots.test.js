// The cell with two robots run from the dashboard, in headless Chromium (demonstrator_test.sh
// brings up examples/cells/two-robots.toml with `skillcell cell up`): the picture shows both
// robots where their bases stand and each one's flange; the Operator runs the process of two
// branches to its end, and the picture then shows each box where its branch put it, and no tool
// on either flange.
"use strict";
const { check, runDemonstrator } = require("./browser");

const object = (id, x, y) => `#scene g[data-object="${id}"][data-x="${x}"][data-y="${y}"]`;
runDemonstrator({
  processIri: "http://skillcell.dev/demo/two-robots#twoBoxesWithTwoRobots",
  stepType: "ChangeToolSkillType",
  shot: "dashboard-two-robots.png",
  before: async (page, wait) => {
    for (const robot of ["left", "right"]) {
      await page.waitForSelector(`#scene g.base[data-robot="${robot}"]`, wait);
      await page.waitForSelector(`#scene g.flange[data-robot="${robot}"][data-tool=""]`, wait);
    }
    const bases = await page.$$eval("#scene g.base text", (ts) => ts.map((t) => t.textContent));
    check(bases.join(",") === "left,right", "the picture shows both robots' bases (" + bases + ")");
    await page.waitForSelector(object("boxL", "0.450", "0.900"), wait);
    await page.waitForSelector(object("boxR", "0.450", "-0.800"), wait);
    check(true, "boxL and boxR stand where the cell file puts them");
  },
  after: async (page, wait) => {
    await page.waitForSelector(object("boxL", "0.250", "0.900"), wait);
    await page.waitForSelector(object("boxR", "0.250", "-0.800"), wait);
    check(true, "each box is where its branch put it");
    for (const robot of ["left", "right"]) {
      await page.waitForSelector(`#scene g.flange[data-robot="${robot}"][data-tool=""]`, wait);
    }
    check(true, "neither robot has a tool on its flange");
  },
});
