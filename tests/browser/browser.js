// What the browser tests share: Debian's Chromium, headless, trusting the dashboard's key by
// its pin as a cell's browsers would trust the cell CA; check(), which ends the test at the
// first failed expectation; and logIn(), a cell user's login with the password `cell up`
// generated in its work directory.
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

module.exports = { launch, check, logIn };
