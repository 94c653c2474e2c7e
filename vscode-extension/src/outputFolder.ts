// Where generated files may go without asking: inside the workspace. No `vscode`
// import here, so that the decision is unit-tested in Node.
//
// A folder is inside the workspace when, after resolving `..` and symbolic links
// (of the part of it that exists), it is one of the workspace folders or lies
// below one. Without workspace folders, the folder of the document stands for
// the workspace (that is where the server writes by default then).

import * as fs from 'node:fs';
import * as path from 'node:path';

export type Realpath = (p: string) => string;

/** What the user answered when asked about a folder outside the workspace. */
export type Answer = 'once' | 'always' | 'cancel';

export interface FolderQuestion {
  /** The folder generation would write to (absolute). */
  folder: string;
  /** The workspace folders it is not in. */
  roots: string[];
}

/** The real path of `p`: symbolic links of its existing part resolved, the rest appended as is. */
export function realPath(p: string, realpath: Realpath = fs.realpathSync.native): string {
  const absolute = path.resolve(p);
  const rest: string[] = [];
  let current = absolute;
  for (;;) {
    try {
      return path.join(realpath(current), ...rest.reverse());
    } catch {
      const parent = path.dirname(current);
      if (parent === current) {
        return absolute;
      }
      rest.push(path.basename(current));
      current = parent;
    }
  }
}

function samePathCase(p: string, platform: NodeJS.Platform): string {
  return platform === 'win32' || platform === 'darwin' ? p.toLowerCase() : p;
}

/** True when `folder` is `root` or lies below it (both already absolute and resolved). */
export function isWithin(folder: string, root: string, platform: NodeJS.Platform = process.platform): boolean {
  const rel = path.relative(samePathCase(root, platform), samePathCase(folder, platform));
  return rel === '' || (!rel.startsWith('..') && !path.isAbsolute(rel));
}

/** The workspace folder that holds `folder`, or undefined when it is outside all of them. */
export function containingRoot(
  folder: string,
  roots: string[],
  realpath: Realpath = fs.realpathSync.native,
  platform: NodeJS.Platform = process.platform,
): string | undefined {
  // Real paths on both sides: a link inside the workspace that leads out of it is outside.
  const target = realPath(folder, realpath);
  return roots.find((root) => isWithin(target, realPath(root, realpath), platform));
}

/**
 * Whether writing into `folder` may go ahead: yes inside the workspace or in a
 * folder the user allowed before; otherwise `ask` decides ('always' also
 * remembers the folder through `remember`).
 */
export async function mayWriteTo(
  folder: string,
  roots: string[],
  options: {
    ask: (question: FolderQuestion) => Promise<Answer>;
    allowed: readonly string[];
    remember: (folder: string) => Promise<void>;
    realpath?: Realpath;
    platform?: NodeJS.Platform;
  },
): Promise<boolean> {
  const realpath = options.realpath ?? fs.realpathSync.native;
  const platform = options.platform ?? process.platform;
  if (containingRoot(folder, roots, realpath, platform) !== undefined) {
    return true;
  }
  const target = realPath(folder, realpath);
  if (options.allowed.some((allowed) => isWithin(target, realPath(allowed, realpath), platform))) {
    return true;
  }
  const answer = await options.ask({ folder: target, roots });
  if (answer === 'always') {
    await options.remember(target);
  }
  return answer !== 'cancel';
}

/**
 * The folder a write command's arguments name: `folder` or `out` of an object
 * argument, or the positional one at `index` (`[uri, target, folder]` for
 * iface.generate, `[uri, folder]` for iface.exportJson).
 */
export function folderArgument(args: unknown[], index: number): string | undefined {
  const first = args[0];
  if (args.length === 1 && typeof first === 'object' && first !== null && !Array.isArray(first)) {
    const record = first as Record<string, unknown>;
    const value = record['folder'] ?? record['out'];
    return typeof value === 'string' && value !== '' ? value : undefined;
  }
  const value = args[index];
  return typeof value === 'string' && value !== '' ? value : undefined;
}
