// Finding the `iface-lsp` executable. No `vscode` import here: the unit tests
// run this module under plain Node.

import { constants, promises as fs } from 'node:fs';
import * as os from 'node:os';
import * as path from 'node:path';

export const SERVER_NAME = 'iface-lsp';

/** Shown when no server is found. */
export const INSTALL_HINT =
  'Install the iface Python package, which provides the `iface-lsp` command, into the Python ' +
  'environment selected for this workspace (for example `pip install iface`, or `pip install -e .` ' +
  'in a checkout of the iface repository), or set `iface.server.path` to the `iface-lsp` executable.';

export interface LocateInput {
  /** Value of `iface.server.path` (may be empty). */
  configuredPath: string;
  /** Python interpreters or environment folders to look in, best first. */
  pythonEnvironments: readonly string[];
  /** Workspace folders (absolute file-system paths). */
  workspaceFolders: readonly string[];
  /** Environment variables (PATH, PATHEXT, VIRTUAL_ENV, CONDA_PREFIX, HOME). */
  env: NodeJS.ProcessEnv;
  platform: NodeJS.Platform;
}

export type LocateResult =
  | { found: true; command: string; source: 'setting' | 'python' | 'workspace-venv' | 'PATH' }
  | { found: false; reason: string; searched: string[] };

/** Expands `~`, `${workspaceFolder}`, `${userHome}` and `${env:NAME}`; resolves against the first folder. */
export function expandPath(value: string, workspaceFolders: readonly string[], env: NodeJS.ProcessEnv): string {
  const home = env['HOME'] ?? env['USERPROFILE'] ?? os.homedir();
  const folder = workspaceFolders[0] ?? '';
  let result = value.trim()
    .replace(/\$\{workspaceFolder\}/g, folder)
    .replace(/\$\{userHome\}/g, home)
    .replace(/\$\{env:([A-Za-z_][A-Za-z0-9_]*)\}/g, (_m: string, name: string) => env[name] ?? '');
  if (result === '~' || result.startsWith('~/') || result.startsWith('~\\')) {
    result = path.join(home, result.slice(1));
  }
  if (!path.isAbsolute(result) && folder !== '' && (result.includes('/') || result.includes('\\'))) {
    result = path.resolve(folder, result);
  }
  return result;
}

async function isExecutableFile(file: string, platform: NodeJS.Platform): Promise<boolean> {
  try {
    const stat = await fs.stat(file);
    if (!stat.isFile()) {
      return false;
    }
    if (platform === 'win32') {
      return true;
    }
    await fs.access(file, constants.X_OK);
    return true;
  } catch {
    return false;
  }
}

function executableNames(name: string, platform: NodeJS.Platform, env: NodeJS.ProcessEnv): string[] {
  if (platform !== 'win32') {
    return [name];
  }
  const exts = (env['PATHEXT'] ?? '.EXE;.CMD;.BAT;.COM').split(';').filter((e) => e !== '');
  return [name, ...exts.map((e) => name + e.toLowerCase()), ...exts.map((e) => name + e)];
}

/** Folders of a Python environment that hold console scripts. */
export function scriptFolders(pythonPathOrEnv: string, platform: NodeJS.Platform): string[] {
  const p = pythonPathOrEnv;
  const base = path.basename(p).toLowerCase();
  const folders: string[] = [];
  if (base.startsWith('python')) {
    // An interpreter: its scripts sit beside it (venv/bin, Scripts) ...
    folders.push(path.dirname(p));
    // ... or in Scripts next to a Windows base interpreter.
    if (platform === 'win32') {
      folders.push(path.join(path.dirname(p), 'Scripts'));
    }
  } else {
    // An environment folder.
    folders.push(path.join(p, platform === 'win32' ? 'Scripts' : 'bin'));
    if (platform === 'win32') {
      folders.push(p);
    }
  }
  return folders;
}

async function findIn(folders: readonly string[], input: LocateInput, searched: string[]): Promise<string | undefined> {
  for (const folder of folders) {
    if (folder === '') {
      continue;
    }
    for (const name of executableNames(SERVER_NAME, input.platform, input.env)) {
      const candidate = path.join(folder, name);
      searched.push(candidate);
      if (await isExecutableFile(candidate, input.platform)) {
        return candidate;
      }
    }
  }
  return undefined;
}

/**
 * Finds the language server: `iface.server.path` when set, else `iface-lsp`
 * in the selected Python environment, then in a `.venv`/`venv` of a workspace
 * folder or the active virtual/conda environment, then on PATH.
 */
export async function locateServer(input: LocateInput): Promise<LocateResult> {
  const searched: string[] = [];
  if (input.configuredPath.trim() !== '') {
    const configured = expandPath(input.configuredPath, input.workspaceFolders, input.env);
    if (path.isAbsolute(configured)) {
      searched.push(configured);
      if (await isExecutableFile(configured, input.platform)) {
        return { found: true, command: configured, source: 'setting' };
      }
      return { found: false, reason: `iface.server.path points to "${configured}", which is not an executable file.`, searched };
    }
    // A bare command name: look it up on PATH.
    const pathDirs = (input.env['PATH'] ?? input.env['Path'] ?? '').split(path.delimiter);
    for (const dir of pathDirs) {
      if (dir === '') {
        continue;
      }
      const candidate = path.join(dir, configured);
      searched.push(candidate);
      if (await isExecutableFile(candidate, input.platform)) {
        return { found: true, command: candidate, source: 'setting' };
      }
    }
    return { found: false, reason: `iface.server.path is "${configured}", which was not found on PATH.`, searched };
  }

  const pythonFolders = input.pythonEnvironments.flatMap((p) => scriptFolders(p, input.platform));
  const fromPython = await findIn(pythonFolders, input, searched);
  if (fromPython !== undefined) {
    return { found: true, command: fromPython, source: 'python' };
  }

  const venvFolders: string[] = [];
  for (const ws of input.workspaceFolders) {
    for (const venv of ['.venv', 'venv']) {
      venvFolders.push(...scriptFolders(path.join(ws, venv), input.platform));
    }
  }
  for (const variable of ['VIRTUAL_ENV', 'CONDA_PREFIX']) {
    const value = input.env[variable];
    if (value !== undefined && value !== '') {
      venvFolders.push(...scriptFolders(value, input.platform));
    }
  }
  const fromVenv = await findIn(venvFolders, input, searched);
  if (fromVenv !== undefined) {
    return { found: true, command: fromVenv, source: 'workspace-venv' };
  }

  const pathDirs = (input.env['PATH'] ?? input.env['Path'] ?? '').split(path.delimiter);
  const fromPath = await findIn(pathDirs, input, searched);
  if (fromPath !== undefined) {
    return { found: true, command: fromPath, source: 'PATH' };
  }
  return { found: false, reason: `${SERVER_NAME} was not found.`, searched };
}
