// End to end, in headless Chromium (Debian's, driven by playwright-core):
// the `likeness` command writes the default avatar and subject 1's
// personalized avatar, `likeness view` serves them with the committed take,
// and the page is checked as a person would use it: both avatars load with
// their 52 ARKit names, jawOpen at 1 changes the pixels of the chin region
// (and hardly those of the brows), the take plays, pauses and scrubs to the
// weights in the file, and a frames.csv from `likeness export` opens too.
// No request leaves the server. Screenshots go to viewer/test-artifacts/.
//
// Needs the page built (npm run build) and Chromium: CHROMIUM names it,
// else /usr/bin/chromium. Prints "N passed, M failed"; exits 1 on a failure.

import { chromium } from 'playwright-core';
import { execFileSync, spawn } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { createInterface } from 'node:readline';
import { fileURLToPath } from 'node:url';

const viewer = dirname(dirname(fileURLToPath(import.meta.url)));
const repo = dirname(viewer);
const artifacts = join(viewer, 'test-artifacts');
const take = join(viewer, 'tests/fixtures/subject-1-take.csv');
const browserPath = process.env.CHROMIUM || '/usr/bin/chromium';

/** A pixel counts as changed when a channel moved by more than this (of 255). */
const PIXEL_CHANGE = 24;

let passed = 0;
let failed = 0;

/** Runs one named check; a failure is reported and ends the run. */
async function check(name, body) {
  try {
    await body();
    passed += 1;
    console.log(`ok - ${name}`);
  } catch (error) {
    failed += 1;
    console.log(`not ok - ${name}\n  ${String(error.stack || error).replaceAll('\n', '\n  ')}`);
    throw error;
  }
}

function assert(condition, message) {
  if (!condition) throw new Error(message);
}

/** Builds the command once and returns the binary's path (wherever CARGO_TARGET_DIR puts it). */
function buildLikeness() {
  const out = execFileSync(
    'cargo',
    ['build', '--quiet', '-p', 'likeness-cli', '--message-format=json'],
    { cwd: repo, encoding: 'utf8', stdio: ['ignore', 'pipe', 'inherit'], maxBuffer: 1 << 28 },
  );
  const artifact = out
    .split('\n')
    .filter((line) => line.startsWith('{'))
    .map((line) => JSON.parse(line))
    .find((m) => m.reason === 'compiler-artifact' && m.target?.name === 'likeness' && m.executable);
  assert(artifact, 'cargo built no likeness binary');
  return artifact.executable;
}

/** Starts `likeness view`; resolves with the process and the address it printed. */
function startViewer(likeness, args) {
  const server = spawn(likeness, ['view', ...args, '--port', '0'], {
    cwd: repo,
    stdio: ['ignore', 'pipe', 'pipe'],
  });
  let said = '';
  server.stderr.on('data', (chunk) => { said += chunk; });
  return new Promise((resolve, reject) => {
    server.on('exit', (code) => reject(new Error(`likeness view exited (${code}) before serving: ${said}`)));
    createInterface({ input: server.stdout }).once('line', (line) => {
      const url = line.replace(/^Likeness viewer: /, '');
      if (url === line) reject(new Error(`likeness view printed ${JSON.stringify(line)}`));
      else resolve({ server, url });
    });
  });
}

/** The page's status (window.viewerState). */
const status = (page) => page.evaluate(() => window.viewerState);

/** Waits until the page has drawn a frame after `renders`. */
async function nextRender(page, renders) {
  await page.waitForFunction((n) => window.viewerState.renders > n, renders, { timeout: 30_000 });
}

/**
 * Changed pixels between two PNG screenshots of the canvas, counted inside
 * rectangles given as fractions of each pane ([x0, y0, x1, y1]); decoded in
 * a blank page of the same browser, so no image library is needed.
 */
async function changedPixels(scratchPage, before, after, panes, rect) {
  return scratchPage.evaluate(async ({ before, after, panes, rect, threshold }) => {
    const decode = async (base64) => {
      const bytes = Uint8Array.from(atob(base64), (c) => c.charCodeAt(0));
      const bitmap = await createImageBitmap(new Blob([bytes], { type: 'image/png' }));
      const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
      const context = canvas.getContext('2d');
      context.drawImage(bitmap, 0, 0);
      return context.getImageData(0, 0, bitmap.width, bitmap.height);
    };
    const [a, b] = [await decode(before), await decode(after)];
    const paneWidth = a.width / panes;
    return Array.from({ length: panes }, (_, pane) => {
      const x0 = Math.floor(pane * paneWidth + rect[0] * paneWidth);
      const x1 = Math.floor(pane * paneWidth + rect[2] * paneWidth);
      const y0 = Math.floor(rect[1] * a.height);
      const y1 = Math.floor(rect[3] * a.height);
      let changed = 0;
      for (let y = y0; y < y1; y++) {
        for (let x = x0; x < x1; x++) {
          const i = 4 * (y * a.width + x);
          const d = Math.max(...[0, 1, 2].map((c) => Math.abs(a.data[i + c] - b.data[i + c])));
          if (d > threshold) changed += 1;
        }
      }
      return { changed, share: changed / ((x1 - x0) * (y1 - y0)) };
    });
  }, { before: before.toString('base64'), after: after.toString('base64'), panes, rect, threshold: PIXEL_CHANGE });
}

/** Column `name` of the committed take, row by row. */
function takeColumn(name) {
  const [header, ...rows] = readFileSync(take, 'utf8').trim().split('\n').map((l) => l.split(','));
  const column = header.indexOf(name);
  return rows.map((row) => Number(row[column]));
}

async function main() {
  assert(existsSync(join(viewer, 'dist/index.html')), 'the page is not built: npm --prefix viewer run build');
  assert(existsSync(browserPath), `no Chromium at ${browserPath} (apt-get install chromium, or set CHROMIUM)`);
  mkdirSync(artifacts, { recursive: true });
  const scratch = mkdtempSync(join(tmpdir(), 'likeness-viewer-'));
  const cleanups = [() => rmSync(scratch, { recursive: true, force: true })];
  try {
    const likeness = buildLikeness();
    const run = (...args) => execFileSync(likeness, args, { cwd: repo, stdio: ['ignore', 'ignore', 'pipe'] });
    const generic = join(scratch, 'default.glb');
    const personal = join(scratch, 'subject-1.glb');
    await check('likeness writes the default avatar and subject 1 implanted into it', async () => {
      run('default-avatar', '--out', generic);
      // The stock face kept, so that both sides are the same avatar before
      // and after implanting (the person's own face is `likeness avatar`'s
      // default on the default avatar, tested in tests/tests/person_face.rs).
      run('avatar', 'sim-data/sessions/subject-1.likeness', '--out', personal,
        '--cache-dir', join(scratch, 'cache'), '--keep-face');
      run('export', 'sim-data/sessions/subject-1.likeness', '--out', join(scratch, 'subject-1'));
    });

    const { server, url } = await startViewer(likeness, [personal, '--generic', generic, '--take', take]);
    cleanups.push(() => server.kill());
    const origin = new URL(url).origin;
    await check(`likeness view serves on 127.0.0.1 (${url})`, async () => {
      assert(origin.startsWith('http://127.0.0.1:'), `served at ${origin}`);
    });

    const browser = await chromium.launch({
      executablePath: browserPath,
      // WebGL on the CPU: ANGLE over SwiftShader (no GPU here).
      args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
    });
    cleanups.push(() => browser.close());
    const page = await browser.newPage({ viewport: { width: 1280, height: 720 } });
    const problems = [];
    page.on('pageerror', (error) => problems.push(`page error: ${error.message}`));
    page.on('console', (m) => m.type() === 'error' && problems.push(`console: ${m.text()}`));
    page.on('request', (request) => {
      const target = request.url();
      if (!target.startsWith(`${origin}/`) && !/^(data|blob):/.test(target)) {
        problems.push(`request outside the server: ${target}`);
      }
    });

    await check('the page loads both avatars with their 52 ARKit names, and the take', async () => {
      await page.goto(url);
      await page.waitForFunction(() => window.viewerState?.ready, null, { timeout: 120_000 });
      const s = await status(page);
      assert(s.error === null, `page error: ${s.error}`);
      assert(s.avatars.length === 2, `${s.avatars.length} avatars shown`);
      assert(s.avatars[0].label === 'generic: default.glb', s.avatars[0].label);
      assert(s.avatars[1].label === 'personalized: subject-1.glb', s.avatars[1].label);
      for (const avatar of s.avatars) {
        const names = Object.keys(avatar.targets);
        assert(names.length === 52, `${avatar.label}: ${names.length} ARKit names`);
        // jawOpen moves the head, teeth, gums and tongue together.
        assert(avatar.targets.jawOpen >= 4, `${avatar.label}: jawOpen on ${avatar.targets.jawOpen} meshes`);
      }
      assert(JSON.stringify(s.avatars[0].faceSize) === JSON.stringify(s.avatars[1].faceSize),
        'the same avatar before and after implanting is framed alike');
      assert(s.stream?.frames === 300 && s.stream.format === 'live-link', JSON.stringify(s.stream));
    });

    const canvas = page.locator('#canvas');
    const shot = async () => canvas.screenshot();
    const scratchPage = await browser.newPage();
    await check('jawOpen at 1 changes the chin region of both avatars, not the brows', async () => {
      let { renders } = await status(page);
      await page.click('#zero');
      await nextRender(page, renders);
      const closed = await shot();
      ({ renders } = await status(page));
      await page.locator('input[data-name="jawOpen"]').fill('1');
      await nextRender(page, renders);
      const s = await status(page);
      assert(s.weights.jawOpen === 1 && s.weights.eyeBlinkLeft === 0, JSON.stringify(s.weights));
      const open = await shot();
      writeFileSync(join(artifacts, 'jaw-closed.png'), closed);
      writeFileSync(join(artifacts, 'jaw-open.png'), open);
      const chin = await changedPixels(scratchPage, closed, open, 2, [0.3, 0.55, 0.7, 0.95]);
      const brows = await changedPixels(scratchPage, closed, open, 2, [0.3, 0.05, 0.7, 0.35]);
      console.log(`  changed pixels, chin: ${chin.map((c) => c.changed)}; brows: ${brows.map((c) => c.changed)}`);
      chin.forEach(({ share }, pane) => {
        assert(share > 0.03, `pane ${pane}: only ${(100 * share).toFixed(1)}% of the chin region changed`);
        assert(brows[pane].changed < 0.2 * chin[pane].changed, `pane ${pane}: the brows changed as much`);
      });
    });

    await check('the take plays: frames advance and the weights follow them', async () => {
      await page.click('#play');
      await page.waitForFunction(() => window.viewerState.frame > 10, null, { timeout: 30_000 });
      const first = await status(page);
      assert(first.playing, 'not playing after Play');
      await page.waitForFunction((f) => window.viewerState.frame > f, first.frame, { timeout: 30_000 });
      const s = await status(page);
      const jaw = takeColumn('JawOpen');
      assert(Math.abs(s.weights.jawOpen - jaw[s.frame]) < 1e-6, `frame ${s.frame}: jawOpen ${s.weights.jawOpen}, file ${jaw[s.frame]}`);
    });

    await check('pause holds the frame; scrubbing shows the file\'s weights', async () => {
      await page.click('#play');
      const paused = await status(page);
      assert(!paused.playing, 'still playing after Pause');
      await page.waitForTimeout(300);
      assert((await status(page)).frame === paused.frame, 'the frame moved while paused');
      // Frame 96 is subject 1's jawOpen peak.
      const { renders } = await status(page);
      await page.locator('#scrub').fill('96');
      await nextRender(page, renders);
      const s = await status(page);
      const [jaw, blink] = [takeColumn('JawOpen'), takeColumn('EyeBlinkLeft')];
      assert(s.frame === 96, `frame ${s.frame} after scrubbing to 96`);
      assert(Math.abs(s.weights.jawOpen - jaw[96]) < 1e-6 && jaw[96] > 0.8, `jawOpen ${s.weights.jawOpen}`);
      assert(Math.abs(s.weights.eyeBlinkLeft - blink[96]) < 1e-6, `eyeBlinkLeft ${s.weights.eyeBlinkLeft}`);
      assert(Math.abs(s.time - 96 / 60) < 1e-9, `time ${s.time}`);
      await page.screenshot({ path: join(artifacts, 'viewer.png') });
    });

    await check('a frames.csv from likeness export opens as a take', async () => {
      await page.setInputFiles('#open-take', join(scratch, 'subject-1/frames.csv'));
      await page.waitForFunction(() => window.viewerState.stream?.format === 'timestamp', null, { timeout: 30_000 });
      const s = await status(page);
      assert(s.stream.frames === 8461 && s.frame === 0 && s.error === null, JSON.stringify(s.stream));
    });

    await check('no page errors, and no request left the server', async () => {
      assert(problems.length === 0, problems.join('\n'));
    });
  } finally {
    for (const cleanup of cleanups.reverse()) await cleanup();
  }
}

const started = Date.now();
try {
  await main();
} catch (error) {
  // A failed check has reported itself; anything else is reported here.
  if (failed === 0) {
    failed = 1;
    console.log(`not ok - ${error.stack || error}`);
  }
}
console.log(`viewer end to end, ${((Date.now() - started) / 1000).toFixed(1)} s`);
console.log(`e2e: ${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
