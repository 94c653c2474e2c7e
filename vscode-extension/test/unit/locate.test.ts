import assert from 'node:assert/strict';
import { chmodSync, mkdirSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { delimiter, join } from 'node:path';
import { after, describe, it } from 'node:test';

import { expandPath, locateServer, scriptFolders } from '../../src/locate';

const root = mkdtempSync(join(tmpdir(), 'iface-locate-'));
after(() => rmSync(root, { recursive: true, force: true }));

function executable(dir: string, name = 'iface-lsp'): string {
  mkdirSync(dir, { recursive: true });
  const file = join(dir, name);
  writeFileSync(file, '#!/bin/sh\n');
  chmodSync(file, 0o755);
  return file;
}

const base = {
  configuredPath: '',
  pythonEnvironments: [] as string[],
  workspaceFolders: [] as string[],
  env: { PATH: '' } as NodeJS.ProcessEnv,
  platform: 'linux' as NodeJS.Platform,
};

describe('locateServer', () => {
  it('uses iface.server.path when it is an executable', async () => {
    const file = executable(join(root, 'configured'));
    const result = await locateServer({ ...base, configuredPath: file });
    assert.deepEqual(result, { found: true, command: file, source: 'setting' });
  });

  it('reports a configured path that does not exist, without searching further', async () => {
    executable(join(root, 'onpath-a'));
    const result = await locateServer({ ...base, configuredPath: join(root, 'missing', 'iface-lsp'), env: { PATH: join(root, 'onpath-a') } });
    assert.equal(result.found, false);
    assert.match(result.found ? '' : result.reason, /not an executable file/);
  });

  it('resolves ${workspaceFolder} in the configured path', async () => {
    const ws = join(root, 'ws-configured');
    const file = executable(join(ws, 'tools'));
    const result = await locateServer({ ...base, configuredPath: '${workspaceFolder}/tools/iface-lsp', workspaceFolders: [ws] });
    assert.deepEqual(result, { found: true, command: file, source: 'setting' });
  });

  it('finds iface-lsp beside the selected Python interpreter', async () => {
    const bin = join(root, 'env1', 'bin');
    const file = executable(bin);
    executable(bin, 'python3');
    const result = await locateServer({ ...base, pythonEnvironments: [join(bin, 'python3')] });
    assert.deepEqual(result, { found: true, command: file, source: 'python' });
  });

  it('finds iface-lsp in a Python environment folder', async () => {
    const env = join(root, 'env2');
    const file = executable(join(env, 'bin'));
    const result = await locateServer({ ...base, pythonEnvironments: [env] });
    assert.deepEqual(result, { found: true, command: file, source: 'python' });
  });

  it('finds iface-lsp in a workspace .venv', async () => {
    const ws = join(root, 'ws-venv');
    const file = executable(join(ws, '.venv', 'bin'));
    const result = await locateServer({ ...base, workspaceFolders: [ws] });
    assert.deepEqual(result, { found: true, command: file, source: 'workspace-venv' });
  });

  it('falls back to PATH', async () => {
    const dir = join(root, 'onpath-b');
    const file = executable(dir);
    const result = await locateServer({ ...base, env: { PATH: ['/nonexistent', dir].join(delimiter) } });
    assert.deepEqual(result, { found: true, command: file, source: 'PATH' });
  });

  it('prefers the Python environment over PATH', async () => {
    const env = join(root, 'env3');
    const file = executable(join(env, 'bin'));
    const dir = join(root, 'onpath-c');
    executable(dir);
    const result = await locateServer({ ...base, pythonEnvironments: [env], env: { PATH: dir } });
    assert.deepEqual(result, { found: true, command: file, source: 'python' });
  });

  it('ignores files that are not executable', async () => {
    const dir = join(root, 'not-exec');
    mkdirSync(dir, { recursive: true });
    writeFileSync(join(dir, 'iface-lsp'), 'data');
    chmodSync(join(dir, 'iface-lsp'), 0o644);
    const result = await locateServer({ ...base, env: { PATH: dir } });
    assert.equal(result.found, false);
    assert.ok(!result.found && result.searched.includes(join(dir, 'iface-lsp')));
  });

  it('says what it searched when nothing is found', async () => {
    const result = await locateServer({ ...base, env: { PATH: join(root, 'empty') } });
    assert.equal(result.found, false);
    assert.ok(!result.found && result.searched.length > 0);
  });
});

describe('scriptFolders and expandPath', () => {
  it('maps interpreters and environment folders to script folders', () => {
    assert.deepEqual(scriptFolders('/e/bin/python3', 'linux'), ['/e/bin']);
    assert.deepEqual(scriptFolders('/e', 'linux'), ['/e/bin']);
  });

  it('expands ~, ${userHome} and ${env:NAME}', () => {
    const env = { HOME: '/home/me', TOOLS: '/opt/tools' };
    assert.equal(expandPath('~/bin/iface-lsp', [], env), '/home/me/bin/iface-lsp');
    assert.equal(expandPath('${userHome}/x', [], env), '/home/me/x');
    assert.equal(expandPath('${env:TOOLS}/iface-lsp', [], env), '/opt/tools/iface-lsp');
    assert.equal(expandPath('iface-lsp', ['/ws'], env), 'iface-lsp');
    assert.equal(expandPath('bin/iface-lsp', ['/ws'], env), '/ws/bin/iface-lsp');
  });
});
