#!/usr/bin/env node
// End-to-end test of the extension in the real VS Code workbench.
//
//   npm run e2e                      # server checks with iface-lsp from PATH, or skipped without it
//   npm run e2e -- --server=real     # iface-lsp must be on PATH
//   npm run e2e -- --server=mock     # the stand-in e2e/mock-server.mjs instead of iface-lsp
//   npm run e2e -- --server=none     # no server: checks the "not found" message instead
//   npm run e2e -- --keep            # keep the temporary folders (printed at the end)
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
  copyFileSync, existsSync, mkdirSync, mkdtempSync, readFileSync, rmSync, statSync, writeFileSync, cpSync,
} from 'node:fs';
import { createServer } from 'node:net';
import { homedir, tmpdir, arch } from 'node:os';
import { delimiter, dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

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

async function check(name, fn) {
  try {
    const detail = await fn();
    record(name, 'pass', typeof detail === 'string' ? detail : '');
    return true;
  } catch (error) {
    record(name, 'fail', error instanceof Error ? error.message.split('\n')[0] : String(error));
    if (activePage !== undefined) {
      const slug = name.replace(/[^A-Za-z0-9]+/g, '-').replace(/^-|-$/g, '').toLowerCase();
      await activePage.screenshot({ path: join(artifacts, `failed-${slug}.png`) }).catch(() => undefined);
    }
    return false;
  }
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

async function runCommand(page, title) {
  await page.keyboard.press('F1');
  const input = page.locator('.quick-input-widget input');
  await input.waitFor({ state: 'visible', timeout: 10000 });
  await input.fill(`>${title}`);
  await page.locator('.quick-input-list .monaco-list-row', { hasText: title }).first().waitFor({ timeout: 10000 });
  await page.keyboard.press('Enter');
}

async function goTo(page, line, column) {
  await page.keyboard.press('Control+G');
  const input = page.locator('.quick-input-widget input');
  await input.waitFor({ state: 'visible', timeout: 10000 });
  await input.fill(`:${line}:${column}`);
  await page.keyboard.press('Enter');
  await page.waitForTimeout(300);
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
  const extensionsDir = join(sandbox, 'extensions');
  const workspace = join(sandbox, 'workspace');
  const config = join(sandbox, 'code-server.yaml');
  const mockLog = join(sandbox, 'mock-server.log');
  cpSync(join(here, 'workspace'), workspace, { recursive: true });
  // The baseline of the compatibility check lives outside the workspace (not a second component in it).
  const baseline = join(sandbox, 'baseline');
  cpSync(join(here, 'baseline'), baseline, { recursive: true });
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
    'editor.minimap.enabled': false,
    'iface.targets': ['ros2'],
    'iface.includePaths': ['idl'],
    'iface.output.folder': 'generated',
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
  const serverLog = [];
  codeServer.stdout.on('data', (d) => serverLog.push(String(d)));
  codeServer.stderr.on('data', (d) => serverLog.push(String(d)));
  await waitForHttp(`http://127.0.0.1:${port}/healthz`, 60000);

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
  page.setDefaultTimeout(30000);
  activePage = page;

  try {
    await page.goto(`http://127.0.0.1:${port}/?folder=${encodeURIComponent(workspace)}`);
    await page.locator('.monaco-workbench').waitFor({ timeout: 60000 });
    await page.locator('.explorer-folders-view .monaco-list-row').first().waitFor({ timeout: 60000 });

    // Open arm.iface with Quick Open.
    await page.keyboard.press('Control+P');
    const quickInput = page.locator('.quick-input-widget input');
    await quickInput.waitFor({ state: 'visible' });
    await quickInput.fill('arm.iface');
    await page.locator('.quick-input-list .monaco-list-row', { hasText: 'arm.iface' }).first().waitFor();
    await page.keyboard.press('Enter');
    await page.locator('.editor-instance .monaco-editor .view-line', { hasText: 'component' }).first().waitFor();
    const source = readFileSync(join(workspace, 'arm.iface'), 'utf8');

    await check('language mode is iface', async () => {
      const mode = page.locator('[id="status.editor.mode"]');
      await waitFor(async () => (await mode.innerText()).trim() === 'iface', 30000, 'the language mode "iface"');
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
      }, 30000, 'coloured keyword, type, string, number and comment tokens');
      return Object.entries(colours).map(([k, v]) => `${k} ${v}`).join(', ');
    });

    await check('status bar item shows the server state', async () => {
      const expected = serverMode === 'none' ? 'not-found' : 'running';
      const item = page.locator(`[aria-label="iface language server ${expected}"]`);
      await item.first().waitFor({ timeout: 60000 });
      return `"iface language server ${expected}"`;
    });

    if (serverMode === 'none') {
      await check('a message says how to install iface-lsp', async () => {
        // A toast, or (once the toast has timed out) an entry of the notification centre.
        await runCommand(page, 'Notifications: Show Notifications');
        const toast = page.locator('.notification-list-item', { hasText: 'iface-lsp' });
        await toast.first().waitFor({ timeout: 30000 });
        const text = await toast.first().innerText();
        await page.screenshot({ path: join(artifacts, 'iface-e2e-not-found.png') });
        await page.keyboard.press('Escape');
        if (!/pip install/.test(text)) throw new Error(`message without install instructions: ${text}`);
        return text.replace(/\s+/g, ' ').slice(0, 120);
      });
      for (const name of ['error squiggle from the server', 'Problems count', 'hover from the server', 'completion from the server',
        'preview command shows generated files read-only', 'compatibility command shows the report', 'system graph command']) {
        record(name, 'skip', 'no language server (install iface-lsp, or --server=mock)');
      }
    } else {
      await check('error squiggle from the server', async () => {
        await page.locator('.editor-instance .monaco-editor .squiggly-error').first().waitFor({ timeout: 60000 });
        return `${await page.locator('.editor-instance .monaco-editor .squiggly-error').count()} squiggle(s)`;
      });

      await check('Problems count', async () => {
        const problems = page.locator('[id="status.problems"]');
        const label = await waitFor(async () => {
          const text = (await problems.getAttribute('aria-label')) ?? (await problems.innerText());
          const errors = /(\d+)\s*error/i.exec(text) ?? /Errors?:\s*(\d+)/i.exec(text);
          return errors !== null && Number(errors[1]) > 0 ? text : undefined;
        }, 30000, 'a non-zero error count in the status bar');
        await page.keyboard.press('Control+Shift+M');
        const rows = page.locator('.markers-panel .monaco-list-row');
        await rows.first().waitFor({ timeout: 15000 });
        const panelText = await page.locator('.markers-panel').innerText();
        if (!panelText.includes('Quaternoin')) throw new Error(`Problems panel does not mention Quaternoin: ${panelText.slice(0, 200)}`);
        return `${label}; panel: ${panelText.replace(/\s+/g, ' ').slice(0, 100)}`;
      });

      await check('hover from the server', async () => {
        const at = positionOf(source, 'publishes JointCommand', 'publishes '.length + 2);
        await page.locator('.editor-instance .monaco-editor .view-lines').first().click();
        await goTo(page, at.line, at.column);
        await page.keyboard.press('Control+K');
        await page.keyboard.press('Control+I');
        const hover = page.locator('.monaco-hover:not(.hidden) .monaco-hover-content, .monaco-hover:not(.hidden) .hover-contents').first();
        const text = await waitFor(async () => {
          const value = (await hover.innerText()).trim();
          return value !== '' ? value : undefined;
        }, 30000, 'a hover');
        await page.screenshot({ path: join(artifacts, 'iface-e2e-hover.png') });
        if (!text.includes('JointCommand')) throw new Error(`hover does not mention JointCommand: ${text.slice(0, 200)}`);
        await page.keyboard.press('Escape');
        return text.replace(/\s+/g, ' ').slice(0, 120);
      });

      await check('completion from the server', async () => {
        // The empty line inside `message JointCommand { ... }`.
        const lines = source.split('\n');
        const emptyLine = lines.findIndex((l, i) => l.trim() === '' && i > 0 && lines.slice(0, i).some((p) => p.startsWith('message JointCommand')));
        await goTo(page, emptyLine + 1, 1);
        await page.keyboard.press('Tab');
        await page.keyboard.press('Control+Space');
        const rows = page.locator('.suggest-widget.visible .monaco-list-row');
        await rows.first().waitFor({ timeout: 30000 });
        const labels = await page.locator('.suggest-widget.visible .monaco-list-row .label-name').allInnerTexts();
        await page.screenshot({ path: join(artifacts, 'iface-e2e-completion.png') });
        await page.keyboard.press('Escape');
        await page.keyboard.press('Control+Z');
        if (labels.length === 0) throw new Error('no completion items');
        if (!labels.some((l) => ['i32', 'float64', 'bool', 'string'].includes(l.trim()))) {
          throw new Error(`no builtin type among the completions: ${labels.slice(0, 8).join(', ')}`);
        }
        return `${labels.length} item(s): ${labels.slice(0, 8).join(', ')}`;
      });

      const activeTab = async () => (await page.locator('.tabs-container .tab.active').first().innerText()).trim();
      const editorText = async () => page.locator('.editor-instance .monaco-editor .view-lines').first().innerText();
      const showArm = async () => {
        await page.keyboard.press('Escape');
        await page.locator('.tabs-container .tab', { hasText: 'arm.iface' }).first().click();
        await waitFor(async () => (await activeTab()).startsWith('arm.iface'), 10000, 'arm.iface to be active');
      };

      await check('preview command shows generated files read-only', async () => {
        await showArm();
        await runCommand(page, 'iface: Preview generated files');
        await page.locator('.quick-input-list .monaco-list-row', { hasText: 'ros2' }).first().waitFor();
        await page.keyboard.press('Enter');
        // Several files: a second pick whose first entry opens them all.
        const openAll = page.locator('.quick-input-list .monaco-list-row', { hasText: 'Open all' });
        await waitFor(async () => (await openAll.count()) > 0 || !(await activeTab()).startsWith('arm.iface'), 60000, 'the preview');
        if ((await openAll.count()) > 0) await page.keyboard.press('Enter');
        const tab = await waitFor(async () => {
          const label = await activeTab();
          return !label.startsWith('arm.iface') ? label : undefined;
        }, 30000, 'a preview tab');
        const text = await waitFor(async () => ((await editorText()).trim() !== '' ? await editorText() : undefined), 10000, 'preview text');
        await page.locator('.editor-instance .monaco-editor .view-lines').first().click();
        await page.keyboard.type('zzz_edit');
        await page.waitForTimeout(300);
        if ((await editorText()).includes('zzz_edit')) throw new Error('the preview document is editable');
        await page.screenshot({ path: join(artifacts, 'iface-e2e-preview.png') });
        return `${tab}: ${text.replace(/\s+/g, ' ').slice(0, 80)}`;
      });

      await check('compatibility command shows the report', async () => {
        await showArm();
        await runCommand(page, 'iface: Check compatibility against…');
        await page.locator('.quick-input-list .monaco-list-row', { hasText: 'iface.compat.baseline' }).first().waitFor();
        await page.keyboard.press('Enter');
        await page.locator('.tabs-container .tab', { hasText: 'arm.compat.txt' }).first().waitFor({ timeout: 60000 });
        const text = await waitFor(async () => ((await editorText()).trim() !== '' ? await editorText() : undefined), 10000, 'report text');
        return text.replace(/\s+/g, ' ').slice(0, 100);
      });

      await check('system graph command', async () => {
        await runCommand(page, 'iface: Show system graph');
        await page.locator('.quick-input-list .monaco-list-row', { hasText: 'mermaid' }).first().waitFor();
        await page.keyboard.press('Enter');
        const tab = page.locator('.tabs-container .tab', { hasText: 'system.mmd' });
        await tab.first().waitFor({ timeout: 60000 });
        const text = await page.locator('.editor-instance .monaco-editor .view-lines').first().innerText();
        if (text.trim() === '') throw new Error('the graph document is empty');
        return text.replace(/\s+/g, ' ').slice(0, 100);
      });

      if (serverMode === 'mock') {
        await check('initializationOptions carry the iface settings', async () => {
          const messages = readFileSync(mockLog, 'utf8').trim().split('\n').map((l) => JSON.parse(l));
          const init = messages.find((m) => m.method === 'initialize');
          const options = init?.params?.initializationOptions;
          const expected = { output: { folder: 'generated' }, targets: ['ros2'], includePaths: ['idl'], compat: { baseline: join(baseline, 'arm.iface') } };
          if (JSON.stringify(options) !== JSON.stringify(expected)) throw new Error(`got ${JSON.stringify(options)}`);
          const graph = messages.find((m) => m.method === 'workspace/executeCommand' && m.params.command === 'iface.graph');
          if (graph === undefined || graph.params.arguments[0].format !== 'mermaid') throw new Error('no iface.graph request with format mermaid');
          return JSON.stringify(options);
        });
      }
    }
    // Back to the top of the source file for the screenshot (Problems panel open).
    await page.keyboard.press('Escape');
    await page.locator('.tabs-container .tab', { hasText: 'arm.iface' }).first().click();
    await page.locator('.editor-instance .monaco-editor .view-lines').first().click();
    await page.keyboard.press('Control+Home');
    await page.waitForTimeout(500);
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
