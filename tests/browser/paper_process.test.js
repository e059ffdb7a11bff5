// The paper's process run from the dashboard, in headless Chromium (paper_process_test.sh
// brings up examples/cells/paper.toml with `skillcell cell up`): the Observer's Run is refused
// by the MES, the Operator's runs the process to its end, and the picture shows the boxes
// where the process put them; a second order, of a process that waits for a gripper no
// component offers, is cancelled from the page and ends cancelled. Every wait is bounded; the
// first failed expectation ends the test with exit code 1.
"use strict";
const { launch, check, logIn: logInTo } = require("./browser");
const fs = require("fs");
const path = require("path");

const url = process.env.DASHBOARD_URL;
const spki = process.env.DASHBOARD_SPKI;
const work = process.env.CELL_WORK_DIR;
const shots = process.env.SCREENSHOT_DIR;
const wait = { timeout: 60000 };
const run = { timeout: 240000 };  // the whole process, on a slow machine
const processIri = "http://skillcell.dev/demo#pickAndPlaceTwoBoxes";

function password(user) {
  return fs.readFileSync(path.join(work, user + ".pw"), "utf8").trim();
}

function logIn(page, user) {
  return logInTo(page, work, user, wait);
}

async function boxAt(page, id) {
  const g = await page.waitForSelector(`#scene g[data-object="${id}"]`, wait);
  return [await g.getAttribute("data-x"), await g.getAttribute("data-y")].join(",");
}

(async () => {
  const browser = await launch(spki);
  try {
    const page = await browser.newPage({ viewport: { width: 1200, height: 900 } });
    await page.goto(url);
    await logIn(page, "observer");

    // Every component of the cell, those without skills too (the LDS, the KB, the world).
    for (const part of ["lds", "kb", "device:world", "mes", "device:ur5"]) {
      await page.waitForSelector(`tr[data-uri="urn:skillcell:${part}"][data-up="true"]`, wait);
    }
    check(true, "the LDS, the KB, the world, the MES and the UR5 are up");

    // The process the KB holds, with its five steps, and the MES ready to run it.
    const row = `#processes tr[data-process="${processIri}"]`;
    await page.waitForSelector(row, wait);
    const steps = await page.textContent(row + " td:nth-child(2)");
    check(steps.includes("1 ChangeToolSkillType") && steps.includes("5 DetachToolSkillType"),
          "the KB's process is listed with its steps (" + steps + ")");
    await page.waitForSelector('#mes-state[data-state="Ready"]', wait);
    check(!(await page.isDisabled(row + " button[data-action=start]")), "the MES is Ready, and Run with it");
    check(await boxAt(page, "boxA") === "0.450,0.150", "boxA stands at its start (0.45, 0.15)");

    // The Observer may watch, not run: the MES refuses her Start.
    await page.click(row + " button[data-action=start]");
    await page.waitForSelector(row + ' .result[data-status="BadUserAccessDenied"]', wait);
    check(true, "the Observer's Run is refused by the MES (BadUserAccessDenied)");
    check(await page.getAttribute("#mes-state", "data-state") === "Ready", "and the MES stays Ready");

    // The Operator runs it to its end; the page follows the steps and the boxes.
    await page.click("#logout");
    await logIn(page, "operator");
    await page.waitForSelector(row + " button[data-action=start]:not([disabled])", wait);
    await page.click(row + " button[data-action=start]");
    await page.waitForSelector(row + ' .result[data-status="Good"]', wait);
    check(true, "the Operator's Run is accepted");
    await page.waitForSelector(row + ' .progress[data-state="running"]', wait);
    check(true, "the run shows as running");
    if (shots) await page.screenshot({ path: path.join(shots, "dashboard-process-running.png"), fullPage: true });
    await page.waitForSelector(row + ' .progress[data-state="completed"]', run);
    const progress = await page.textContent(row + " .progress");
    check(progress.includes("5/5 steps"), "the run completed its five steps (" + progress + ")");
    await page.waitForFunction(
      () => document.querySelectorAll('#runs .run[data-state="completed"] .step[data-state="finished"]').length === 5,
      null, wait);
    check(true, "the timeline shows the five steps finished");
    await page.waitForSelector('#scene g[data-object="boxA"][data-x="0.250"][data-y="0.350"]', wait);
    await page.waitForSelector('#scene g[data-object="boxB"][data-x="0.250"][data-y="-0.200"]', wait);
    check(true, "the picture shows boxA at (0.25, 0.35) and boxB at (0.25, -0.2)");
    await page.waitForSelector('#scene g.flange[data-tool=""]', wait);
    check(true, "and no tool on the flange");
    if (shots) await page.screenshot({ path: path.join(shots, "dashboard-process.png"), fullPage: true });

    // An order cancelled from the page: the Operator runs the process that waits for a
    // gripper's MoveGripper (no tool is mounted, so none is offered: paper_process_test.sh
    // added it), order 2; it waits at the MES until the page cancels it, and ends cancelled.
    const waiting = '#processes tr[data-process="http://skillcell.dev/test/orders#waitsForAGripper"]';
    await page.waitForSelector(waiting + " button[data-action=start]:not([disabled])", wait);
    await page.click(waiting + " button[data-action=start]");
    await page.waitForSelector(waiting + ' .result[data-status="Good"]', wait);
    const second = '#runs .run[data-run="2"]';
    await page.waitForSelector(second + " button[data-action=cancel]", wait);
    check(true, "order 2 waits for a gripper, with its Cancel button");
    await page.click(second + " button[data-action=cancel]");
    await page.waitForSelector(second + ' .result[data-status="Good"]', wait);
    check(true, "the MES accepted the cancel");
    await page.waitForSelector(second + '[data-state="cancelled"]', wait);
    check(!(await page.$(second + " button[data-action=cancel]")), "order 2, cancelled from the page, ends cancelled");

    // Guessing a password: the first five wrong ones are only wrong; from the sixth on, each
    // locks the name, for 1 s, 2 s, 4 s … The test waits out each lock as the page says
    // (Retry-After), until the eighth wrong one has locked it for 4 s; the right password,
    // sent at once, must wait too. (A 1 s lock was too short on a loaded machine: the
    // right password came after it.)
    await page.click("#logout");
    await page.waitForSelector("#login:not([hidden])", wait);
    await page.fill("#login-user", "engineer");
    const answer = async (pw) => {
      await page.evaluate(() => { document.getElementById("login-error").textContent = ""; });
      await page.fill("#login-password", pw);
      await page.click("#login button[type=submit]");
      return (await page.waitForSelector("#login-error:not(:empty)", wait)).textContent();
    };
    let wrong = 0, locked = 0;
    for (let i = 0; i < 30 && wrong < 8; ++i) {
      const said = await answer("guess-" + i);
      const lock = said.match(/Too many wrong passwords.* try again in (\d+) s/);
      if (lock) {
        check(wrong >= 6, `locked only after six wrong passwords (after ${wrong})`);
        ++locked;
        await page.waitForTimeout(Number(lock[1]) * 1000);  // the lock the server set, waited out
      } else {
        check(said.includes("Wrong user or password"), `a wrong password is refused (${said})`);
        ++wrong;
      }
    }
    check(wrong === 8, `eight wrong passwords answered, ${locked} guesses refused while locked`);
    const right = await answer(password("engineer"));
    check(right.includes("Too many wrong passwords"), "while locked, even the right password waits (429)");
    check(await page.isHidden("#cell"), "and the page stays at the login");
  } finally {
    await browser.close();
  }
})().catch((e) => {
  console.error("FAIL " + e.message);
  process.exit(1);
});
