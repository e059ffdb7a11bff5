// The dashboard's push latency in headless Chromium (dashboard_latency.sh sets the cell up).
"use strict";
const { launch } = require("../tests/browser/browser");

const runs = Number(process.env.RUNS || 50);
const wait = { timeout: 30000 };

function percentile(sorted, p) {
  return sorted[Math.min(sorted.length - 1, Math.floor((p / 100) * sorted.length))];
}

(async () => {
  const browser = await launch(process.env.DASHBOARD_SPKI);
  try {
    const page = await browser.newPage();
    await page.goto(process.env.DASHBOARD_URL);
    await page.waitForSelector("#login:not([hidden])", wait);
    await page.fill("#login-user", "otto");
    await page.fill("#login-password", "otto-secret-3");
    await page.click("#login button[type=submit]");
    const grasp = '#skills tr[data-key^="urn:test:gripper"]';
    await page.waitForSelector(grasp + '[data-state="Ready"]', wait);
    // Each new last transition of the gripper's row, with the moment the page showed it.
    await page.evaluate((sel) => {
      window.seen = [];
      let last = "";
      const note = () => {
        const row = document.querySelector(sel);
        if (row && row.dataset.lastAt && row.dataset.lastAt !== last) {
          last = row.dataset.lastAt;
          window.seen.push({ at: last, shown: Date.now() });
        }
      };
      new MutationObserver(note).observe(document.getElementById("skills"),
                                         { childList: true, subtree: true, attributes: true });
    }, grasp);
    for (let i = 0; i < runs; i++) {
      const before = await page.evaluate(() => window.seen.length);
      await page.click(grasp + " button[data-action=start]");
      await page.waitForFunction((n) => window.seen.length > n, before, wait);
      await page.waitForSelector(grasp + '[data-state="Ready"]', wait);
    }
    const seen = await page.evaluate(() => window.seen);
    const ms = seen.map((s) => s.shown - Date.parse(s.at)).filter((x) => !isNaN(x)).sort((a, b) => a - b);
    if (ms.length === 0) throw new Error("no transition was seen");
    const p50 = percentile(ms, 50);
    const p99 = percentile(ms, 99);
    console.log(`dashboard push latency (server transition -> page DOM), ${ms.length} transitions ` +
                `of ${runs} runs: p50 ${p50.toFixed(0)} ms, p99 ${p99.toFixed(0)} ms, ` +
                `min ${ms[0].toFixed(0)} ms, max ${ms[ms.length - 1].toFixed(0)} ms ` +
                `(goal: p50 <= 100 ms: ${p50 <= 100 ? "met" : "NOT met"})`);
  } finally {
    await browser.close();
  }
})().catch((e) => {
  console.error("dashboard_latency: " + e.message);
  process.exit(1);
});
