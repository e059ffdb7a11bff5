// What the browser tests share: Debian's Chromium, headless, trusting the dashboard's key by
// its pin as a cell's browsers would trust the cell CA; and check(), which ends the test at
// the first failed expectation.
"use strict";
const { chromium } = require("playwright-core");

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

module.exports = { launch, check };
