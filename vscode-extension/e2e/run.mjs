#!/usr/bin/env node
// End-to-end test of the extension in the real VS Code workbench.
//
//   npm run e2e                      # server checks with iface-lsp from PATH, or skipped without it
//   npm run e2e -- --server=real     # iface-lsp must be on PATH
//   npm run e2e -- --server=mock     # the stand-in e2e/mock-server.mjs instead of iface-lsp
//   npm run e2e -- --server=none     # no server: checks the "not found" message instead
//   npm run e2e -- --keep            # keep the temporary folders (printed at the end)
//   npm run e2e -- --fail-once=STEP  # fail the first attempt of a step (slug): tests the retry
//
// What it does:
//  1. packages the extension (`npm run package` -> dist/iface.vsix);
//  2. installs code-server (pinned in e2e/code-server/package-lock.json) with
//     `npm ci` into a cache folder, $IFACE_E2E_CACHE or ~/.cache/iface-vscode-e2e,
//     once; code-server is not a devDependency because it is ~300 MB and
//     builds native modules (see README.md, "End-to-end test");
//  3. installs the .vsix into a fresh code-server profile and starts it on
//     127.0.0.1 with telemetry, update checks and the extension gallery off;
//  4. opens e2e/workspace/arm.iface in headless Chromium (Debian's
//     /usr/bin/chromium, or $IFACE_E2E_CHROMIUM) driven by playwright-core,
//     and checks the language mode, token colours, the server's squiggle,
//     Problems count, hover and completion, the status bar item and the
//     system-graph command;
//  5. saves screenshots in e2e/artifacts/ and prints "N passed, N failed, N skipped".
//
// Missing Debian packages (chromium; libkrb5-dev, ripgrep and build tools for
// code-server's native modules) are installed with apt-get when running as
// root; otherwise the script says what to install.

import { execFileSync, spawn, spawnSync } from 'node:child_process';
import {
  copyFileSync, existsSync, mkdirSync, mkdtempSync, readFileSync, readdirSync, rmSync, statSync, writeFileSync, cpSync,
} from 'node:fs';
import { createServer } from 'node:net';
import { homedir, tmpdir, arch } from 'node:os';
import { delimiter, dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

import { decodePng, inkCount } from './png.mjs';

const CODE_SERVER_VERSION = '4.100.3';
// code-server 4.100.3 ships lib/vscode/npm-shrinkwrap.json with @vscode/ripgrep 1.15.11,
// whose postinstall downloads ripgrep v13.0.0-10 from GitHub unless it finds this cache.
const RIPGREP_PACKAGE_VERSION = '1.15.11';
const RIPGREP_RELEASE = 'v13.0.0-10';

const here = dirname(fileURLToPath(import.meta.url));
const extensionRoot = join(here, '..');
const artifacts = join(here, 'artifacts');
const args = new Set(process.argv.slice(2));
const serverArg = [...args].find((a) => a.startsWith('--server='))?.slice('--server='.length) ?? process.env.IFACE_E2E_SERVER ?? 'auto';
const keep = args.has('--keep');
// Makes the first attempt of the named step (its slug, e.g. preview-command-shows-generated-files-read-only)
// fail after it ran, to test the retry and the evidence kept on failure.
const failOnce = [...args].find((a) => a.startsWith('--fail-once='))?.slice('--fail-once='.length);
const chromiumPath = process.env.IFACE_E2E_CHROMIUM ?? '/usr/bin/chromium';
const cacheRoot = process.env.IFACE_E2E_CACHE ?? join(process.env.XDG_CACHE_HOME ?? join(homedir(), '.cache'), 'iface-vscode-e2e');

const results = [];
let codeServer;
let context;
/** The workbench page, for screenshots of failed checks. */
let activePage;
let sandbox;

function log(message) {
  console.log(`[e2e] ${message}`);
}

function record(name, status, detail = '') {
  results.push({ name, status, detail });
  const mark = status === 'pass' ? 'PASS' : status === 'fail' ? 'FAIL' : 'SKIP';
  console.log(`${mark}  ${name}${detail ? ` — ${detail}` : ''}`);
}

/** Lines of code-server's output so far (kept in artifacts on failure and at the end). */
const serverLog = [];
/** The profile folder of code-server (its logs hold the language server's output channel). */
let userDataDir;
/** Puts the workbench back in a known state before a step is tried again. */
let resetUi = async () => undefined;

function slugOf(name) {
  return name.replace(/[^A-Za-z0-9]+/g, '-').replace(/^-|-$/g, '').toLowerCase();
}

function filesUnder(dir) {
  const out = [];
  for (const entry of existsSync(dir) ? readdirSync(dir, { withFileTypes: true }) : []) {
    const path = join(dir, entry.name);
    if (entry.isDirectory()) out.push(...filesUnder(path));
    else out.push(path);
  }
  return out;
}

/**
 * Keeps what explains a failure: a screenshot, code-server's log and the iface
 * output channel (the language server's log, as VS Code writes it), under
 * e2e/artifacts/failed-<step>[-attempt-N].*; returns their paths.
 */
async function keepEvidence(name, attempt) {
  const base = join(artifacts, `failed-${slugOf(name)}${attempt > 0 ? `-attempt-${attempt + 1}` : ''}`);
  const kept = [];
  if (activePage !== undefined) {
    const shot = `${base}.png`;
    if (await activePage.screenshot({ path: shot }).then(() => true, () => false)) kept.push(shot);
  }
  writeFileSync(`${base}-code-server.log`, serverLog.join(''));
  kept.push(`${base}-code-server.log`);
  if (userDataDir !== undefined) {
    const logs = filesUnder(join(userDataDir, 'logs'));
    const iface = logs.filter((f) => /iface/i.test(f.split(/[\\/]/).pop() ?? ''));
    const host = logs.filter((f) => /exthost\d*\.log$/.test(f));
    const text = [...iface, ...host].map((f) => `==> ${f} <==\n${readFileSync(f, 'utf8')}`).join('\n');
    writeFileSync(`${base}-iface-lsp.log`, text === '' ? 'no iface output channel log was written\n' : text);
    kept.push(`${base}-iface-lsp.log`);
  }
  return kept;
}

/**
 * One step of the test. A step that fails is tried once more from a reset
 * workbench (a loaded machine can lose a keystroke to a re-render); what
 * explains each failure is kept and named.
 */
async function check(name, fn, { retry = true } = {}) {
  const attempts = retry ? 2 : 1;
  for (let attempt = 0; attempt < attempts; attempt += 1) {
    try {
      const detail = await fn();
      if (attempt === 0 && failOnce === slugOf(name)) throw new Error(`--fail-once=${failOnce}`);
      const note = attempt > 0 ? ' (passed when tried again)' : '';
      record(name, 'pass', `${typeof detail === 'string' ? detail : ''}${note}`);
      return true;
    } catch (error) {
      const message = error instanceof Error ? error.message.split('\n')[0] : String(error);
      const kept = await keepEvidence(name, attempt).catch((e) => [`(could not keep evidence: ${e})`]);
      if (attempt + 1 < attempts) {
        log(`"${name}" failed: ${message}; trying once more. Kept: ${kept.join(', ')}`);
        await resetUi().catch((e) => log(`resetting the workbench failed: ${e instanceof Error ? e.message : e}`));
        continue;
      }
      record(name, 'fail', `${message} — kept: ${kept.join(', ')}`);
      return false;
    }
  }
  return false;
}

function which(command, envPath = process.env.PATH ?? '') {
  for (const dir of envPath.split(delimiter)) {
    if (dir === '') continue;
    const candidate = join(dir, command);
    try {
      if (statSync(candidate).isFile()) {
        execFileSync('test', ['-x', candidate]);
        return candidate;
      }
    } catch {
      // not here
    }
  }
  return undefined;
}

// ---- Prerequisites ----------------------------------------------------------

let aptUpdated = false;
function ensureDebianPackages(packages, present, why) {
  if (present()) return;
  const isRoot = typeof process.getuid === 'function' && process.getuid() === 0;
  if (!isRoot || which('apt-get') === undefined) {
    throw new Error(`${why} is missing: install it with \`apt-get install -y ${packages.join(' ')}\` (as root), then run again.`);
  }
  log(`installing ${packages.join(' ')} (${why}) with apt-get`);
  const env = { ...process.env, DEBIAN_FRONTEND: 'noninteractive' };
  if (!aptUpdated) {
    execFileSync('apt-get', ['update'], { stdio: 'inherit', env });
    aptUpdated = true;
  }
  execFileSync('apt-get', ['install', '-y', '--no-install-recommends', ...packages], { stdio: 'inherit', env });
  if (!present()) throw new Error(`${packages.join(' ')} installed, but ${why} is still missing`);
}

function npmCommand() {
  return process.platform === 'win32' ? 'npm.cmd' : 'npm';
}

function run(command, commandArgs, options = {}) {
  const result = spawnSync(command, commandArgs, { stdio: 'inherit', ...options });
  if (result.status !== 0) {
    throw new Error(`${command} ${commandArgs.join(' ')} exited with ${result.status ?? result.signal}`);
  }
}

function seedRipgrepCache() {
  const rg = which('rg');
  if (rg === undefined) return;
  const target = arch() === 'arm64' ? 'aarch64-unknown-linux-musl' : 'x86_64-unknown-linux-musl';
  const cache = join(tmpdir(), `vscode-ripgrep-cache-${RIPGREP_PACKAGE_VERSION}`);
  const asset = join(cache, `ripgrep-${RIPGREP_RELEASE}-${target}.tar.gz`);
  if (existsSync(asset)) return;
  mkdirSync(cache, { recursive: true });
  const staging = mkdtempSync(join(tmpdir(), 'iface-e2e-rg-'));
  copyFileSync(rg, join(staging, 'rg'));
  execFileSync('tar', ['czf', asset, '-C', staging, 'rg']);
  rmSync(staging, { recursive: true, force: true });
  log(`seeded the ripgrep download cache with ${rg}`);
}

function ensureCodeServer() {
  const dir = join(cacheRoot, `code-server-${CODE_SERVER_VERSION}`);
  const bin = join(dir, 'node_modules', '.bin', 'code-server');
  const marker = join(dir, '.installed');
  const lock = readFileSync(join(here, 'code-server', 'package-lock.json'), 'utf8');
  if (existsSync(marker) && existsSync(bin) && readFileSync(marker, 'utf8') === lock) {
    return bin;
  }
  const major = Number(process.versions.node.split('.')[0]);
  if (major !== 20) {
    throw new Error(`code-server ${CODE_SERVER_VERSION} needs Node 20 (this is ${process.versions.node})`);
  }
  // Native modules of VS Code (kerberos, node-pty, spdlog, ...) are built with node-gyp.
  ensureDebianPackages(['build-essential', 'python3'], () => which('g++') !== undefined && which('make') !== undefined, 'a C++ tool chain');
  ensureDebianPackages(['libkrb5-dev'], () => existsSync('/usr/include/gssapi/gssapi.h'), 'the Kerberos headers (gssapi.h)');
  ensureDebianPackages(['ripgrep'], () => which('rg') !== undefined, 'ripgrep');
  seedRipgrepCache();
  rmSync(dir, { recursive: true, force: true });
  mkdirSync(dir, { recursive: true });
  copyFileSync(join(here, 'code-server', 'package.json'), join(dir, 'package.json'));
  copyFileSync(join(here, 'code-server', 'package-lock.json'), join(dir, 'package-lock.json'));
  log(`installing code-server ${CODE_SERVER_VERSION} into ${dir} (a few minutes, once)`);
  run(npmCommand(), ['ci', '--no-audit', '--no-fund'], {
    cwd: dir,
    env: {
      ...process.env,
      // code-server's postinstall refuses to run as root without it, and its
      // nested installs call npx, which must not prompt.
      npm_config_unsafe_perm: 'true',
      npm_config_yes: 'true',
    },
  });
  writeFileSync(marker, lock);
  return bin;
}

function freePort() {
  return new Promise((resolve, reject) => {
    const server = createServer();
    server.unref();
    server.on('error', reject);
    server.listen(0, '127.0.0.1', () => {
      const address = server.address();
      server.close(() => resolve(address.port));
    });
  });
}

async function waitForHttp(url, timeoutMs) {
  const deadline = Date.now() + timeoutMs;
  for (;;) {
    try {
      const response = await fetch(url);
      if (response.status < 500) return;
    } catch {
      // not up yet
    }
    if (Date.now() > deadline) throw new Error(`${url} did not answer within ${timeoutMs / 1000} s`);
    await new Promise((r) => setTimeout(r, 500));
  }
}

async function waitFor(fn, timeoutMs, what) {
  const deadline = Date.now() + timeoutMs;
  let last;
  for (;;) {
    try {
      const value = await fn();
      if (value) return value;
    } catch (error) {
      last = error;
    }
    if (Date.now() > deadline) {
      throw new Error(`timed out after ${timeoutMs / 1000} s waiting for ${what}${last ? ` (${last.message ?? last})` : ''}`);
    }
    await new Promise((r) => setTimeout(r, 250));
  }
}

// ---- Workbench helpers ----------------------------------------------------------
//
// Every wait is on a condition (an element, a focus, a text), never on time
// alone; the timeouts are generous because a loaded 2-core machine can take many
// seconds for what is instant on an idle one.

/** Default timeout of one wait (Playwright actions and waitFor). */
const STEP_TIMEOUT = 60000;
/** For the workbench and the language server to come up. */
const STARTUP_TIMEOUT = 180000;

const QUICK_INPUT = '.quick-input-widget';

/** True when the quick input is shown and its text box has the keyboard focus. */
async function quickInputFocused(page) {
  return page.evaluate((selector) => {
    const widget = document.querySelector(selector);
    if (!widget || widget.style.display === 'none' || widget.offsetParent === null) return false;
    const active = document.activeElement;
    return active !== null && active.tagName === 'INPUT' && widget.contains(active);
  }, QUICK_INPUT);
}

async function quickInputHidden(page) {
  return page.evaluate((selector) => {
    const widget = document.querySelector(selector);
    return !widget || widget.style.display === 'none' || widget.offsetParent === null;
  }, QUICK_INPUT);
}

/** Closes whatever quick input, dialog or widget is open: Escape until the quick input is gone. */
async function closeOverlays(page) {
  await waitFor(async () => {
    if ((await quickInputHidden(page)) && (await page.locator('.monaco-dialog-box').count()) === 0) return true;
    await page.keyboard.press('Escape');
    return false;
  }, STEP_TIMEOUT, 'the quick input and dialogs to close');
}

/**
 * Opens a quick input with `key` (F1, Control+P, Control+G), types `text` and
 * waits until the focused row contains `row` (unless `row` is null). The key
 * is pressed again only after the quick input was seen closed, so a slow
 * workbench never gets a second F1 that cycles or toggles.
 */
async function quickInput(page, key, text, row) {
  await closeOverlays(page);
  let pressedAt = 0;
  await waitFor(async () => {
    if (await quickInputFocused(page)) return true;
    if (Date.now() - pressedAt > 15000 && (await quickInputHidden(page))) {
      await page.keyboard.press(key);
      pressedAt = Date.now();
    }
    return false;
  }, STEP_TIMEOUT, `the quick input of ${key}`);
  // Keyboard input goes to the focused text box: no actionability wait that a re-render can stall.
  await page.keyboard.press('Control+A');
  await page.keyboard.insertText(text);
  if (row !== null) {
    await focusedRow(page, row);
  }
}

/** Waits until the focused row of the quick input contains `text`. */
async function focusedRow(page, text) {
  const focused = page.locator(`${QUICK_INPUT} .quick-input-list .monaco-list-row.focused`, { hasText: text });
  await focused.first().waitFor({ state: 'visible', timeout: STEP_TIMEOUT });
}

/** Runs a command of the Command Palette by its title. */
async function runCommand(page, title) {
  await quickInput(page, 'F1', `>${title}`, title);
  await page.keyboard.press('Enter');
}

/** Accepts the focused row of a quick pick that a command showed, once it contains `text`. */
async function accept(page, text) {
  await waitFor(async () => !(await quickInputHidden(page)), STEP_TIMEOUT, `a quick pick offering ${text}`);
  await focusedRow(page, text);
  await page.keyboard.press('Enter');
}

/** The label of the active tab of the active editor group. */
async function activeTab(page) {
  const tab = page.locator('.editor-group-container.active .tabs-container .tab.active').first();
  return (await tab.count()) > 0 ? (await tab.innerText()).trim() : '';
}

/** Makes `name` the active editor (Quick Open: no click on a tab that may be covered). */
async function focusFile(page, name) {
  if (!(await activeTab(page)).startsWith(name)) {
    await quickInput(page, 'Control+P', name, name);
    await page.keyboard.press('Enter');
  }
  await waitFor(async () => (await activeTab(page)).startsWith(name), STEP_TIMEOUT, `${name} to be the active editor`);
  await page.locator('.editor-instance .monaco-editor textarea').first().focus();
}

/** Line and column of the cursor, from the status bar ("Ln 12, Col 3"). */
async function cursor(page) {
  const text = await page.locator('[id="status.editor.selection"]').first().innerText().catch(() => '');
  const m = /Ln (\d+), Col (\d+)/.exec(text);
  return m ? { line: Number(m[1]), column: Number(m[2]) } : undefined;
}

async function goTo(page, line, column) {
  await quickInput(page, 'Control+G', `:${line}:${column}`, null);
  await page.keyboard.press('Enter');
  await waitFor(async () => {
    const at = await cursor(page);
    return at !== undefined && at.line === line && at.column === column;
  }, STEP_TIMEOUT, `the cursor at ${line}:${column}`);
}

/** The text and colour of every token span of the visible editor lines. */
async function editorTokens(page) {
  return page.evaluate(() => {
    const editor = document.querySelector('.editor-instance .monaco-editor');
    if (!editor) return { foreground: '', tokens: [] };
    const lines = [...editor.querySelectorAll('.view-lines .view-line')];
    const tokens = [];
    for (const line of lines) {
      for (const span of line.querySelectorAll(':scope > span > span')) {
        tokens.push({ text: span.textContent ?? '', color: getComputedStyle(span).color });
      }
    }
    return { foreground: getComputedStyle(editor.querySelector('.view-lines')).color, tokens };
  });
}

/** Index of the first line containing `text` (1-based) and its column (1-based). */
function positionOf(source, text, offset = 0) {
  const lines = source.split('\n');
  for (let i = 0; i < lines.length; i += 1) {
    const column = lines[i].indexOf(text);
    if (column >= 0) return { line: i + 1, column: column + 1 + offset };
  }
  throw new Error(`fixture has no ${text}`);
}

/** The frame of the active webview's content (VS Code nests it in two iframes). */
async function webviewFrame(page, marker) {
  return waitFor(async () => {
    for (const frame of page.frames()) {
      if (frame.name() === 'active-frame' || frame.url().includes('fake.html')) {
        const found = await frame.locator(marker).count().catch(() => 0);
        if (found > 0) return frame;
      }
    }
    return undefined;
  }, STEP_TIMEOUT, `a webview showing ${marker}`);
}

// ---- Main ------------------------------------------------------------------------

async function main() {
  mkdirSync(artifacts, { recursive: true });
  ensureDebianPackages(['chromium'], () => existsSync(chromiumPath), `Chromium (${chromiumPath})`);

  let serverMode = serverArg;
  const ifaceLsp = which('iface-lsp');
  if (serverMode === 'auto') {
    serverMode = ifaceLsp !== undefined ? 'real' : 'none';
    if (serverMode === 'none') {
      log('iface-lsp is not on PATH: the server checks are skipped (install the Python package, or use --server=mock).');
    }
  }
  if (!['real', 'mock', 'none'].includes(serverMode)) throw new Error(`unknown --server=${serverMode}`);
  log(`server mode: ${serverMode}${serverMode === 'real' ? ` (${ifaceLsp ?? 'iface-lsp missing'})` : ''}`);

  if (!args.has('--no-package')) {
    log('packaging the extension');
    run(npmCommand(), ['run', 'package', '--silent'], { cwd: extensionRoot });
  }
  const vsix = join(extensionRoot, 'dist', 'iface.vsix');
  if (!existsSync(vsix)) throw new Error(`${vsix} is missing`);

  const codeServerBin = ensureCodeServer();
  const { chromium } = await import('playwright-core');

  sandbox = mkdtempSync(join(tmpdir(), 'iface-e2e-'));
  const userData = join(sandbox, 'user-data');
  userDataDir = userData;
  const extensionsDir = join(sandbox, 'extensions');
  const workspace = join(sandbox, 'workspace');
  const config = join(sandbox, 'code-server.yaml');
  const mockLog = join(sandbox, 'mock-server.log');
  cpSync(join(here, 'workspace'), workspace, { recursive: true });
  // The baseline of the compatibility check lives outside the workspace (not a second component in it).
  const baseline = join(sandbox, 'baseline');
  cpSync(join(here, 'baseline'), baseline, { recursive: true });
  // Generate writes here only when the user confirms: it is outside the workspace.
  const outside = join(sandbox, 'outside-output');
  mkdirSync(join(userData, 'User'), { recursive: true });
  writeFileSync(config, 'auth: none\ncert: false\n');

  const env = {
    ...process.env,
    // No extension gallery: an empty gallery configuration turns it off.
    EXTENSIONS_GALLERY: '{}',
    // The extension host gets this environment as is, not the one of a login
    // shell (VS Code skips resolving the shell environment when VSCODE_CLI=1).
    VSCODE_CLI: '1',
    IFACE_MOCK_LOG: mockLog,
  };
  if (serverMode === 'none') {
    // Hide iface-lsp from the extension host.
    env.PATH = (env.PATH ?? '').split(delimiter).filter((d) => d !== '' && !existsSync(join(d, 'iface-lsp'))).join(delimiter);
    delete env.VIRTUAL_ENV;
    delete env.CONDA_PREFIX;
  }

  const settings = {
    'workbench.startupEditor': 'none',
    'workbench.tips.enabled': false,
    'workbench.enableExperiments': false,
    'workbench.colorTheme': 'Default Dark Modern',
    'workbench.secondarySideBar.defaultVisibility': 'hidden',
    'workbench.editor.enablePreview': false,
    'files.autoSave': 'off',
    'telemetry.telemetryLevel': 'off',
    'update.mode': 'none',
    'extensions.autoCheckUpdates': false,
    'extensions.autoUpdate': false,
    'extensions.ignoreRecommendations': true,
    'security.workspace.trust.enabled': false,
    'git.enabled': false,
    'chat.commandCenter.enabled': false,
    'editor.wordBasedSuggestions': 'off',
    'editor.snippetSuggestions': 'none',
    'editor.quickSuggestions': { other: false, comments: false, strings: false },
    'editor.hover.delay': 100,
    'editor.minimap.enabled': false,
    'iface.targets': ['ros2'],
    'iface.includePaths': ['idl'],
    'iface.output.folder': outside,
    'iface.compat.baseline': join(baseline, 'arm.iface'),
  };
  if (serverMode === 'mock') {
    settings['iface.server.path'] = process.execPath;
    settings['iface.server.args'] = [join(here, 'mock-server.mjs'), '--stdio'];
  }
  writeFileSync(join(userData, 'User', 'settings.json'), JSON.stringify(settings, null, 2));

  const common = ['--config', config, '--user-data-dir', userData, '--extensions-dir', extensionsDir];
  log('installing the .vsix into code-server');
  run(codeServerBin, [...common, '--install-extension', vsix, '--force'], { env });

  const port = await freePort();
  log(`starting code-server ${CODE_SERVER_VERSION} on 127.0.0.1:${port}`);
  codeServer = spawn(codeServerBin, [
    ...common,
    '--bind-addr', `127.0.0.1:${port}`,
    '--auth', 'none',
    '--disable-telemetry',
    '--disable-update-check',
    '--disable-workspace-trust',
    '--disable-getting-started-override',
    '--ignore-last-opened',
    workspace,
  ], { env, detached: true, stdio: ['ignore', 'pipe', 'pipe'] });
  codeServer.stdout.on('data', (d) => serverLog.push(String(d)));
  codeServer.stderr.on('data', (d) => serverLog.push(String(d)));
  await waitForHttp(`http://127.0.0.1:${port}/healthz`, STARTUP_TIMEOUT);

  const profile = join(sandbox, 'chromium-profile');
  context = await chromium.launchPersistentContext(profile, {
    executablePath: chromiumPath,
    headless: true,
    viewport: { width: 1400, height: 900 },
    args: [
      '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
    ],
  });
  const page = context.pages()[0] ?? (await context.newPage());
  page.setDefaultTimeout(STEP_TIMEOUT);
  activePage = page;
  const source = readFileSync(join(workspace, 'arm.iface'), 'utf8');
  const editorText = async () => page.locator('.editor-instance .monaco-editor .view-lines').first().innerText();
  const textOf = async (tab) => {
    await waitFor(async () => (await activeTab(page)).startsWith(tab), STEP_TIMEOUT, `${tab} to be the active editor`);
    return waitFor(async () => ((await editorText()).trim() !== '' ? editorText() : undefined), STEP_TIMEOUT, `the text of ${tab}`);
  };
  // Back to the state the steps start from: one editor group with arm.iface, unchanged, and no other editor.
  resetUi = async () => {
    await closeOverlays(page);
    if ((await page.locator('.editor-group-container').count()) > 1) {
      await runCommand(page, 'View: Single Column Editor Layout');
      await waitFor(async () => (await page.locator('.editor-group-container').count()) === 1, STEP_TIMEOUT, 'one editor group');
    }
    await focusFile(page, 'arm.iface');
    if ((await page.locator('.tabs-container .tab.active.dirty').count()) > 0) {
      await runCommand(page, 'File: Revert File');
      await waitFor(async () => (await page.locator('.tabs-container .tab.active.dirty').count()) === 0, STEP_TIMEOUT, 'arm.iface to be reverted');
    }
    await runCommand(page, 'View: Close All Editors');
    await waitFor(async () => (await page.locator('.tabs-container .tab').count()) === 0, STEP_TIMEOUT, 'no editor open');
    await focusFile(page, 'arm.iface');
  };

  try {
    await page.goto(`http://127.0.0.1:${port}/?folder=${encodeURIComponent(workspace)}`);
    await page.locator('.monaco-workbench').waitFor({ timeout: STARTUP_TIMEOUT });
    await page.locator('.explorer-folders-view .monaco-list-row').first().waitFor({ timeout: STARTUP_TIMEOUT });

    await check('arm.iface opens', async () => {
      await focusFile(page, 'arm.iface');
      await page.locator('.editor-instance .monaco-editor .view-line', { hasText: 'component' }).first().waitFor();
      return 'with Quick Open';
    });

    await check('language mode is iface', async () => {
      const mode = page.locator('[id="status.editor.mode"]');
      await waitFor(async () => (await mode.innerText()).trim() === 'iface', STEP_TIMEOUT, 'the language mode "iface"');
      return 'status bar shows "iface"';
    });

    await check('tokens are coloured by the TextMate grammar', async () => {
      const colours = await waitFor(async () => {
        const { foreground, tokens } = await editorTokens(page);
        const colourOf = (predicate) => tokens.find((t) => predicate(t.text.trim()))?.color;
        const found = {
          keyword: colourOf((t) => t === 'message'),
          builtin: colourOf((t) => t === 'float64'),
          string: colourOf((t) => t.includes('1.2.0')),
          number: colourOf((t) => t === '1.5'),
          comment: colourOf((t) => t.startsWith('/**')),
        };
        const values = Object.values(found);
        if (values.some((c) => c === undefined || c === foreground)) return undefined;
        if (new Set(values).size < 4) return undefined;
        return found;
      }, STEP_TIMEOUT, 'coloured keyword, type, string, number and comment tokens');
      return Object.entries(colours).map(([k, v]) => `${k} ${v}`).join(', ');
    });

    await check('status bar item shows the server state', async () => {
      const expected = serverMode === 'none' ? 'not-found' : 'running';
      const item = page.locator(`[aria-label="iface language server ${expected}"]`);
      await item.first().waitFor({ timeout: STARTUP_TIMEOUT });
      return `"iface language server ${expected}"`;
    });

    if (serverMode === 'none') {
      await check('a message says how to install iface-lsp', async () => {
        // A toast, or (once the toast has timed out) an entry of the notification centre.
        await runCommand(page, 'Notifications: Show Notifications');
        const toast = page.locator('.notification-list-item', { hasText: 'iface-lsp' });
        await toast.first().waitFor();
        const text = await toast.first().innerText();
        await page.screenshot({ path: join(artifacts, 'iface-e2e-not-found.png') });
        await page.keyboard.press('Escape');
        if (!/pip install/.test(text)) throw new Error(`message without install instructions: ${text}`);
        return text.replace(/\s+/g, ' ').slice(0, 120);
      });
      for (const name of ['error squiggle from the server', 'Problems count', 'hover from the server', 'completion from the server',
        'preview command shows generated files read-only', 'compatibility command shows the report', 'system graph picture',
        'system graph as text', 'Generate asks before writing outside the workspace']) {
        record(name, 'skip', 'no language server (install iface-lsp, or --server=mock)');
      }
    } else {
      await check('error squiggle from the server', async () => {
        await focusFile(page, 'arm.iface');
        await page.locator('.editor-instance .monaco-editor .squiggly-error').first().waitFor({ timeout: STARTUP_TIMEOUT });
        return `${await page.locator('.editor-instance .monaco-editor .squiggly-error').count()} squiggle(s)`;
      });

      await check('Problems count', async () => {
        const problems = page.locator('[id="status.problems"]');
        const label = await waitFor(async () => {
          const text = (await problems.getAttribute('aria-label')) ?? (await problems.innerText());
          const errors = /(\d+)\s*error/i.exec(text) ?? /Errors?:\s*(\d+)/i.exec(text);
          return errors !== null && Number(errors[1]) > 0 ? text : undefined;
        }, STEP_TIMEOUT, 'a non-zero error count in the status bar');
        await runCommand(page, 'View: Focus Problems');
        const panel = page.locator('.markers-panel');
        const panelText = await waitFor(async () => {
          const text = await panel.first().innerText().catch(() => '');
          return text.includes('Quaternoin') ? text : undefined;
        }, STEP_TIMEOUT, 'the Problems panel to mention Quaternoin');
        return `${label}; panel: ${panelText.replace(/\s+/g, ' ').slice(0, 100)}`;
      });

      await check('hover from the server', async () => {
        await focusFile(page, 'arm.iface');
        const at = positionOf(source, 'publishes JointCommand', 'publishes '.length + 2);
        await goTo(page, at.line, at.column);
        const hover = page.locator('.monaco-hover:not(.hidden) .monaco-hover-content, .monaco-hover:not(.hidden) .hover-contents').first();
        let pressedAt = 0;
        const text = await waitFor(async () => {
          const value = (await hover.count()) > 0 ? (await hover.innerText()).trim() : '';
          if (value.includes('JointCommand')) return value;
          if (Date.now() - pressedAt > 10000) {
            // Show Hover again while the server has not answered yet: the first request may have come before it was ready.
            await page.keyboard.press('Control+K');
            await page.keyboard.press('Control+I');
            pressedAt = Date.now();
          }
          return undefined;
        }, STEP_TIMEOUT, 'a hover mentioning JointCommand');
        await page.screenshot({ path: join(artifacts, 'iface-e2e-hover.png') });
        await page.keyboard.press('Escape');
        return text.replace(/\s+/g, ' ').slice(0, 120);
      });

      await check('completion from the server', async () => {
        await focusFile(page, 'arm.iface');
        // The empty line inside `message JointCommand { ... }`.
        const lines = source.split('\n');
        const emptyLine = lines.findIndex((l, i) => l.trim() === '' && i > 0 && lines.slice(0, i).some((p) => p.startsWith('message JointCommand')));
        await goTo(page, emptyLine + 1, 1);
        await page.keyboard.press('Tab');
        await waitFor(async () => (await page.locator('.tabs-container .tab.active.dirty').count()) > 0, STEP_TIMEOUT, 'the Tab to be typed');
        const rows = page.locator('.suggest-widget.visible .monaco-list-row');
        let pressedAt = 0;
        const labels = await waitFor(async () => {
          if ((await rows.count()) > 0) {
            const found = await page.locator('.suggest-widget.visible .monaco-list-row .label-name').allInnerTexts();
            if (found.some((l) => ['i32', 'float64', 'bool', 'string'].includes(l.trim()))) return found;
          }
          if (Date.now() - pressedAt > 10000) {
            await page.keyboard.press('Escape');
            await page.keyboard.press('Control+Space');
            pressedAt = Date.now();
          }
          return undefined;
        }, STEP_TIMEOUT, 'completion items with a builtin type');
        await page.screenshot({ path: join(artifacts, 'iface-e2e-completion.png') });
        await page.keyboard.press('Escape');
        await page.keyboard.press('Control+Z');
        await waitFor(async () => (await page.locator('.tabs-container .tab.active.dirty').count()) === 0, STEP_TIMEOUT, 'the edit to be undone');
        return `${labels.length} item(s): ${labels.slice(0, 8).join(', ')}`;
      });

      await check('preview command shows generated files read-only', async () => {
        await focusFile(page, 'arm.iface');
        await runCommand(page, 'iface: Preview generated files');
        await accept(page, 'ros2');
        // Several files: a second pick whose first entry opens them all ("Open all N files").
        const tabs = page.locator('.editor-group-container.active .tabs-container .tab');
        const before = await tabs.count();
        const openAll = page.locator(`${QUICK_INPUT} .monaco-list-row.focused`, { hasText: 'Open all' });
        const shown = await waitFor(async () => {
          if (!(await quickInputHidden(page)) && (await openAll.count()) > 0) return 'pick';
          const tab = await activeTab(page);
          return tab !== '' && !tab.startsWith('arm.iface') ? 'tab' : undefined;
        }, STEP_TIMEOUT, 'the preview');
        let files = 1;
        if (shown === 'pick') {
          files = Number(/Open all (\d+)/.exec(await openAll.first().innerText())?.[1] ?? '1');
          await page.keyboard.press('Enter');
        }
        // The files open one after the other; the last one gets the focus. Type only then.
        await waitFor(async () => (await tabs.count()) >= before + files, STEP_TIMEOUT, `${files} preview tab(s)`);
        const [tab, text] = await waitFor(async () => {
          const label = await activeTab(page);
          const shownText = await editorText();
          const focused = await page.evaluate(() => document.activeElement?.closest('.editor-group-container.active .monaco-editor') != null);
          return focused && label !== '' && !label.startsWith('arm.iface') && shownText.trim() !== '' ? [label, shownText] : undefined;
        }, STEP_TIMEOUT, 'the last preview with the keyboard focus');
        await page.keyboard.type('zzz_edit');
        // Either VS Code says the editor is read-only, or the text changed: whichever comes first.
        const outcome = await waitFor(async () => {
          if ((await page.locator('.monaco-editor-overlaymessage', { hasText: /read-only|Cannot edit/i }).count()) > 0) return 'refused';
          if ((await editorText()).includes('zzz_edit')) return 'edited';
          return undefined;
        }, STEP_TIMEOUT, 'the read-only message');
        if (outcome === 'edited') throw new Error('the preview document is editable');
        await page.screenshot({ path: join(artifacts, 'iface-e2e-preview.png') });
        return `${tab} (typing refused: read-only): ${text.replace(/\s+/g, ' ').slice(0, 80)}`;
      });

      await check('compatibility command shows the report', async () => {
        await focusFile(page, 'arm.iface');
        await runCommand(page, 'iface: Check compatibility against…');
        await accept(page, 'iface.compat.baseline');
        const text = await textOf('arm.compat.txt');
        if (serverMode === 'real' && !text.includes('verdict:')) throw new Error(`no verdict in the report: ${text.slice(0, 200)}`);
        return text.replace(/\s+/g, ' ').slice(0, 100);
      });

      await check('system graph picture', async () => {
        await focusFile(page, 'arm.iface');
        await runCommand(page, 'iface: Show system graph');
        const panelTab = page.locator('.tabs-container .tab.active', { hasText: 'System graph' });
        await waitFor(async () => (await panelTab.count()) > 0, STEP_TIMEOUT, 'the System graph panel');
        const frame = await webviewFrame(page, 'body[data-rendered]');
        const rendered = await frame.locator('body').getAttribute('data-rendered');
        if (rendered !== '2') throw new Error(`the panel drew ${rendered} components, not 2 (status: ${await frame.locator('#status').innerText()})`);
        const names = (await frame.locator('svg.graph .component .name').allTextContents()).map((n) => n.trim());
        if (names.join(',') !== 'arm_controller,motion_planner') throw new Error(`components drawn: ${names.join(', ')}`);
        const conflicts = await frame.locator('svg.graph .edge.conflict').count();
        if (conflicts < 1) throw new Error('no link drawn as a conflict');
        // The picture itself: a screenshot of the panel must not be blank, and the conflict shows red.
        const shot = join(artifacts, 'iface-e2e-graph.png');
        const png = await page.locator('iframe.webview.ready').first().screenshot({ path: shot });
        const ink = inkCount(decodePng(png));
        const share = ink.ink / ink.pixels;
        if (share < 0.01 || ink.red < 20) {
          throw new Error(`the graph looks blank: ${ink.ink} of ${ink.pixels} pixels differ from the background ${ink.background}, ${ink.red} red`);
        }
        // Clicking a box goes to the component's declaration.
        await frame.locator('svg.graph .component', { hasText: 'motion_planner' }).first().click();
        await waitFor(async () => (await activeTab(page)).startsWith('planner.iface'), STEP_TIMEOUT, 'planner.iface to open');
        const at = await waitFor(async () => {
          const c = await cursor(page);
          return c !== undefined && c.line === 2 ? c : undefined;
        }, STEP_TIMEOUT, 'the cursor on the component declaration (line 2)');
        // One editor group again, so that the next steps act on the editor they open.
        await runCommand(page, 'View: Single Column Editor Layout');
        await waitFor(async () => (await page.locator('.editor-group-container').count()) === 1, STEP_TIMEOUT, 'one editor group');
        return `${names.length} boxes, ${conflicts} red link(s); ${(100 * share).toFixed(1)}% of ${ink.pixels} pixels drawn, ${ink.red} red; click -> planner.iface:${at.line}:${at.column}; ${shot}`;
      });

      await check('system graph as text', async () => {
        await focusFile(page, 'arm.iface');
        await runCommand(page, 'iface: Show system graph as text');
        await accept(page, 'mermaid');
        const text = await textOf('system.mmd');
        return text.replace(/\s+/g, ' ').slice(0, 100);
      });

      await check('Generate asks before writing outside the workspace', async () => {
        await focusFile(page, 'planner.iface'); // arm.iface has an error: nothing to generate
        const dialog = page.locator('.monaco-dialog-box');
        const askGenerate = async () => {
          await runCommand(page, 'iface: Generate for target…');
          await accept(page, 'ros2');
          await dialog.first().waitFor();
          const text = (await dialog.first().innerText()).replace(/\s+/g, ' ');
          if (!text.includes('outside the workspace') || !text.includes(outside)) throw new Error(`unexpected dialog: ${text.slice(0, 200)}`);
          return text;
        };
        const button = (label) => dialog.locator('.dialog-buttons a.monaco-button, .dialog-buttons .monaco-button', { hasText: label }).first();
        await askGenerate();
        await page.screenshot({ path: join(artifacts, 'iface-e2e-generate-outside.png') });
        await page.keyboard.press('Escape'); // the dialog's Cancel
        await waitFor(async () => (await dialog.count()) === 0, STEP_TIMEOUT, 'the dialog to close');
        const requests = () => (serverMode === 'mock' && existsSync(mockLog)
          ? readFileSync(mockLog, 'utf8').trim().split('\n').map((l) => JSON.parse(l))
            .filter((m) => m.method === 'workspace/executeCommand' && m.params.command === 'iface.generate')
          : []);
        if (existsSync(outside) || requests().length > 0) throw new Error('generated although the user cancelled');
        await askGenerate();
        await button('Generate').press('Enter');
        if (serverMode === 'real') {
          const written = await waitFor(async () => {
            const files = filesUnder(join(outside, 'ros2'));
            return files.some((f) => f.endsWith('package.xml')) ? files : undefined;
          }, STEP_TIMEOUT, `generated files in ${outside}`);
          await page.locator('.notification-toast', { hasText: 'generated' }).first().waitFor();
          return `Cancel wrote nothing; Generate wrote ${written.length} file(s) into ${outside}/ros2`;
        }
        await waitFor(async () => requests().some((m) => m.params.arguments[0].out === outside), STEP_TIMEOUT, 'an iface.generate request');
        return 'Cancel sent nothing; Generate sent iface.generate with the outside folder';
      });

      if (serverMode === 'mock') {
        await check('initializationOptions carry the iface settings', async () => {
          const messages = readFileSync(mockLog, 'utf8').trim().split('\n').map((l) => JSON.parse(l));
          const init = messages.find((m) => m.method === 'initialize');
          const options = init?.params?.initializationOptions;
          const expected = { output: { folder: outside }, targets: ['ros2'], includePaths: ['idl'], compat: { baseline: join(baseline, 'arm.iface') } };
          if (JSON.stringify(options) !== JSON.stringify(expected)) throw new Error(`got ${JSON.stringify(options)}`);
          const graph = messages.find((m) => m.method === 'workspace/executeCommand' && m.params.command === 'iface.graph');
          if (graph === undefined || graph.params.arguments[0].format !== 'json') throw new Error('no iface.graph request with format json');
          return JSON.stringify(options);
        }, { retry: false });
      }
    }
    // Back to the top of the source file for the screenshot (Problems panel open).
    await resetUi().catch(() => undefined);
    await page.keyboard.press('Control+Home');
    await waitFor(async () => (await cursor(page))?.line === 1, STEP_TIMEOUT, 'the cursor at the top').catch(() => undefined);
  } finally {
    const shot = join(artifacts, 'iface-e2e.png');
    await page.screenshot({ path: shot }).catch(() => undefined);
    log(`screenshot: ${shot}`);
    writeFileSync(join(artifacts, 'code-server.log'), serverLog.join(''));
  }
}

async function cleanup() {
  if (context) await context.close().catch(() => undefined);
  if (codeServer && codeServer.exitCode === null && codeServer.pid !== undefined) {
    try {
      process.kill(-codeServer.pid, 'SIGTERM');
    } catch {
      // already gone
    }
  }
  if (sandbox) {
    if (keep) log(`kept ${sandbox}`);
    else rmSync(sandbox, { recursive: true, force: true });
  }
}

let exitCode = 0;
try {
  await main();
} catch (error) {
  record('e2e harness', 'fail', error instanceof Error ? error.message : String(error));
}
await cleanup();
const passed = results.filter((r) => r.status === 'pass').length;
const failed = results.filter((r) => r.status === 'fail').length;
const skipped = results.filter((r) => r.status === 'skip').length;
if (failed > 0) exitCode = 1;
console.log(`e2e: ${passed} passed, ${failed} failed, ${skipped} skipped`);
process.exit(exitCode);
