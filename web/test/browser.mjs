// Debian's chromium driven by playwright-core (never a downloaded browser). Headless, with the
// background networking off (this machine has no network) and a fresh profile each time.
import { createRequire } from 'node:module';
import { existsSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = resolve(dirname(fileURLToPath(import.meta.url)), '..');
const modules = resolve(process.env.GRIP_WEB_MODULES || join(root, 'node_modules'));
const { chromium } = createRequire(join(modules, 'noop.js'))('playwright-core');

export const CHROMIUM = process.env.GRIP_CHROMIUM || '/usr/bin/chromium';

export async function launch() {
  if (!existsSync(CHROMIUM)) throw new Error(`${CHROMIUM} not found: bash scripts/setup.sh installs Debian's chromium`);
  const profile = mkdtempSync(join(tmpdir(), 'grip-chromium-'));
  // A persistent context is how playwright takes a --user-data-dir: a new empty one each time.
  const browser = await chromium.launchPersistentContext(profile, {
    executablePath: CHROMIUM,
    headless: true,
    viewport: { width: 1200, height: 760 },
    args: [
      '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
      '--disable-sync', '--no-first-run', '--disable-quic',
    ],
  });
  const close = browser.close.bind(browser);
  browser.close = async () => {
    await close();
    rmSync(profile, { recursive: true, force: true });
  };
  return browser;
}

// A page that fails the test on any uncaught error in the page.
export async function newPage(browser, errors) {
  const page = await browser.newPage();
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => {
    if (m.type() === 'error') errors.push(m.text());
  });
  return page;
}

// Waits until the viewer finished its n-th load (or failed it).
export async function waitLoaded(page, n = 1) {
  await page.waitForFunction((k) => window.gripViewer && window.gripViewer.state().loads >= k, n, { timeout: 60000 });
  return page.evaluate(() => window.gripViewer.state());
}
