// The dashboard in headless Chromium (dashboard_test.sh prepares the cell). Every wait is
// bounded; the first failed expectation ends the test with exit code 1.
"use strict";
const { launch, check } = require("./browser");
const path = require("path");

const url = process.env.DASHBOARD_URL;
const spki = process.env.DASHBOARD_SPKI;
const gripperPid = Number(process.env.GRIPPER_PID);
const shots = process.env.SCREENSHOT_DIR;
const wait = { timeout: 30000 };

(async () => {
  const browser = await launch(spki);
  try {
    const page = await browser.newPage({ viewport: { width: 1200, height: 700 } });
    const requests = [];
    page.on("request", (r) => requests.push(new URL(r.url()).pathname));

    // Anonymous: the login form, and no way to the events.
    await page.goto(url);
    await page.waitForSelector("#login:not([hidden])", wait);
    check(await page.isHidden("#cell"), "the cell is hidden before the login");
    const anonymous = await page.evaluate(async () => (await fetch("/events")).status);
    check(anonymous === 401, "GET /events without a session is 401 (was " + anonymous + ")");

    await page.fill("#login-user", "olga");
    await page.fill("#login-password", "wrong");
    await page.click("#login button[type=submit]");
    await page.waitForSelector("#login-error:text('Wrong user or password')", wait);
    check(true, "a wrong password is refused");

    await page.fill("#login-password", "olga-secret-1");
    requests.length = 0;  // from the login on
    await page.click("#login button[type=submit]");
    await page.waitForSelector("#cell:not([hidden])", wait);
    check(await page.isHidden("#login"), "the login form is gone");
    const who = await page.textContent("#user");
    check(who.startsWith("olga") && who.includes("Observer"), "logged in as olga, an Observer");

    // The components appear, up, with their skills and states.
    await page.waitForSelector('tr[data-uri="urn:test:robot"][data-up="true"]', wait);
    await page.waitForSelector('tr[data-uri="urn:test:gripper"][data-up="true"]', wait);
    check(true, "both components appear, up");
    await page.waitForFunction(
      () => document.querySelectorAll('#skills tr[data-state="Ready"]').length >= 3, null, wait);
    check(true, "their three skills are shown Ready");
    // The world's scene, from above: the dock with its tool, the box where it stands.
    await page.waitForSelector('#scene g[data-dock="dockP"][data-tool="parallel"]', wait);
    const box = await page.waitForSelector('#scene g[data-object="boxA"]', wait);
    check((await box.getAttribute("data-x")) === "0.450" && (await box.getAttribute("data-y")) === "0.150",
          "the scene shows dockP with its tool and boxA at (0.45, 0.15)");

    // Bad requests get a precise answer: an unknown action, an unknown skill.
    const bad = await page.evaluate(async () => {
      const post = async (form) => {
        const r = await fetch("/api/skill", { method: "POST", body: new URLSearchParams(form) });
        return r.status + " " + (await r.json()).status;
      };
      return [await post({ key: "x", action: "explode" }), await post({ key: "urn:none ns=1;i=1", action: "start" })];
    });
    check(bad[0] === "400 BadInvalidArgument", "an unknown action is 400 BadInvalidArgument (" + bad[0] + ")");
    check(bad[1] === "409 BadNodeIdUnknown", "an unknown skill is 409 BadNodeIdUnknown (" + bad[1] + ")");

    // The Observer may watch, not run: the gripper's server refuses her Start.
    const grasp = '#skills tr[data-key^="urn:test:gripper"]';
    await page.click(grasp + " button[data-action=start]");
    await page.waitForSelector(grasp + ' .result[data-status="BadUserAccessDenied"]', wait);
    check(true, "the Observer's Start is refused by the component (BadUserAccessDenied)");
    check((await page.getAttribute(grasp, "data-state")) === "Ready", "and the skill stays Ready");

    // The Operator runs it: the page shows its transitions as they happen, pushed by the
    // skill's events.
    await page.click("#logout");
    await page.waitForSelector("#login:not([hidden])", wait);
    await page.fill("#login-user", "otto");
    await page.fill("#login-password", "otto-secret-3");
    requests.length = 0;  // from this login on
    await page.click("#login button[type=submit]");
    await page.waitForSelector("#cell:not([hidden])", wait);
    await page.waitForSelector(grasp + '[data-state="Ready"]', wait);
    await page.click(grasp + " button[data-action=start]");
    await page.waitForSelector(grasp + ' .result[data-status="Good"]', wait);
    await page.waitForFunction((sel) => {
      const row = document.querySelector(sel);
      return row && row.dataset.state === "Ready" && row.textContent.includes("Running→Ready");
    }, grasp, wait);
    check(true, "the Operator's Start runs the skill: Running→Ready appears, Ready again");
    if (shots) await page.screenshot({ path: path.join(shots, "dashboard.png"), fullPage: true });

    // Unplugged: the gripper's server stops, and the page shows it gone.
    process.kill(gripperPid, "SIGTERM");
    await page.waitForSelector('tr[data-uri="urn:test:gripper"][data-up="false"]', wait);
    const robotUp = await page.getAttribute('tr[data-uri="urn:test:robot"]', "data-up");
    check(robotUp === "true", "the gripper goes down, the robot stays up");
    await page.waitForFunction(
      () => !document.querySelector('#skills tr[data-key^="urn:test:gripper"]'), null, wait);
    check(true, "the gripper's skill leaves the skill table");
    if (shots) await page.screenshot({ path: path.join(shots, "dashboard-gripper-gone.png"), fullPage: true });

    // Live by push: one event stream since the Operator's login, no polling.
    const streams = requests.filter((p) => p === "/events").length;
    const mes = requests.filter((p) => p === "/api/me").length;
    check(streams === 1, "one event stream for the whole session (was " + streams + ")");
    const posts = requests.filter((p) => p === "/api/skill").length;
    check(posts === 1, "one action since the Operator's login, the Start (" + posts + ")");
    check(mes === 0, "no polling of /api/me (" + mes + " requests)");

    await page.click("#logout");
    await page.waitForSelector("#login:not([hidden])", wait);
    const after = await page.evaluate(async () => (await fetch("/api/me")).status);
    check(after === 401, "after logout the session is gone");
  } finally {
    await browser.close();
  }
})().catch((e) => {
  console.error("FAIL " + e.message);
  process.exit(1);
});
