// What the page test looks at, as a person would: the state the page reports (loading, ready,
// error), the frame counter, and where each clip's colour is in a screenshot.
import { PNG } from 'pngjs';

export const BROWSER_ARGS = ['--headless', '--no-sandbox', '--disable-gpu', '--enable-unsafe-swiftshader', '--disable-quic',
  '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'];

function hueOf(r, g, b) {
  const max = Math.max(r, g, b);
  const min = Math.min(r, g, b);
  if (max === min) return { hue: 0, saturation: 0, value: max / 255 };
  const d = max - min;
  let hue = max === r ? (g - b) / d : max === g ? 2 + (b - r) / d : 4 + (r - g) / d;
  hue = (hue * 60 + 360) % 360;
  return { hue, saturation: d / max, value: max / 255 };
}

// Opens `url`, waits until the page has drawn its first frame or shown an error.
export async function openPage(browser, url, { width = 1000, height = 640 } = {}) {
  const page = await browser.newPage({ viewport: { width, height } });
  const problems = [];
  page.on('pageerror', (error) => problems.push(error.message));
  await page.goto(url);
  await page.waitForSelector('body[data-viewer-state="ready"], body[data-viewer-state="error"]', { timeout: 30000 });
  page.problems = problems;
  return page;
}

export const viewerState = (page) => page.evaluate(() => document.body.dataset.viewerState);
export const shownFrame = async (page) => Number(await page.getAttribute('.mv-frame-counter', 'data-frame'));
export const errorText = (page) => page.evaluate(() => [...document.querySelectorAll('[role=alert]')].map((e) => e.textContent).join('\n'));

// Screenshot (saved to `path`) and, per colour, the pixels of that hue inside the 3D view (legend
// and error banner left out): count, bounding box and centre, as fractions of the view's size.
export async function colourRegions(page, colours, path) {
  const png = PNG.sync.read(await page.screenshot({ path }));
  const rect = async (selector) => page.evaluate((s) => {
    const e = document.querySelector(s);
    if (!e || e.hidden || e.childElementCount === 0) return null;
    const r = e.getBoundingClientRect();
    return { left: r.left, top: r.top, right: r.right, bottom: r.bottom };
  }, selector);
  const view = await rect('.mv-viewport');
  const holes = [await rect('.mv-legend'), await rect('.mv-errors')].filter(Boolean);
  const targets = colours.map((c) => hueOf(parseInt(c.slice(1, 3), 16), parseInt(c.slice(3, 5), 16), parseInt(c.slice(5, 7), 16)).hue);
  const stats = targets.map(() => ({ count: 0, minX: 1, maxX: 0, minY: 1, maxY: 0, sumX: 0 }));
  const scale = png.width / page.viewportSize().width;
  for (let y = Math.ceil(view.top * scale); y < Math.floor(view.bottom * scale); y++) {
    for (let x = Math.ceil(view.left * scale); x < Math.floor(view.right * scale); x++) {
      if (holes.some((h) => x >= h.left * scale && x < h.right * scale && y >= h.top * scale && y < h.bottom * scale)) continue;
      const i = (y * png.width + x) * 4;
      const { hue, saturation, value } = hueOf(png.data[i], png.data[i + 1], png.data[i + 2]);
      if (saturation < 0.45 || value < 0.3) continue;
      targets.forEach((target, k) => {
        if (Math.min(Math.abs(hue - target), 360 - Math.abs(hue - target)) > 12) return;
        const s = stats[k];
        const fx = (x / scale - view.left) / (view.right - view.left);
        const fy = (y / scale - view.top) / (view.bottom - view.top);
        s.count++;
        s.sumX += fx;
        s.minX = Math.min(s.minX, fx);
        s.maxX = Math.max(s.maxX, fx);
        s.minY = Math.min(s.minY, fy);
        s.maxY = Math.max(s.maxY, fy);
      });
    }
  }
  const aspect = (view.right - view.left) / (view.bottom - view.top);
  return stats.map((s) => ({ count: s.count, centreX: s.count ? s.sumX / s.count : NaN, width: (s.maxX - s.minX) * aspect,
    height: s.maxY - s.minY, left: s.minX, right: s.maxX, top: s.minY, bottom: s.maxY }));
}
