// Reading the answers of the server's workspace/executeCommand. No `vscode`
// import here. The server is the authority on content; the client only
// checks shapes so that a surprise shows as a message, not an exception.

export interface GeneratedFile {
  path: string;
  text: string;
}

function isRecord(value: unknown): value is Record<string, unknown> {
  return typeof value === 'object' && value !== null && !Array.isArray(value);
}

/** `iface.preview` answers `{ files: [{ path, text }] }`. */
export function parseFiles(result: unknown): GeneratedFile[] | undefined {
  const files = isRecord(result) ? result['files'] : result;
  if (!Array.isArray(files)) {
    return undefined;
  }
  const parsed: GeneratedFile[] = [];
  for (const item of files) {
    if (isRecord(item) && typeof item['path'] === 'string' && typeof item['text'] === 'string') {
      parsed.push({ path: item['path'], text: item['text'] });
    } else {
      return undefined;
    }
  }
  return parsed;
}

/** `iface.compat` and `iface.graph` answer text (a string, or `{ text }`). */
export function asText(result: unknown): string {
  if (typeof result === 'string') {
    return result;
  }
  if (isRecord(result) && typeof result['text'] === 'string') {
    return result['text'];
  }
  if (result === null || result === undefined) {
    return '';
  }
  return JSON.stringify(result, null, 2);
}

/** Paths that `iface.generate` reports as written, in any of the likely shapes. */
export function writtenPaths(result: unknown): string[] {
  if (!isRecord(result)) {
    return [];
  }
  const files = result['files'] ?? result['written'] ?? result['paths'];
  if (!Array.isArray(files)) {
    return [];
  }
  return files.flatMap((item: unknown) => {
    if (typeof item === 'string') {
      return [item];
    }
    if (isRecord(item) && typeof item['path'] === 'string') {
      return [item['path']];
    }
    return [];
  });
}

/** A path of a generated file made safe to use inside a virtual document URI. */
export function previewPath(target: string, filePath: string): string {
  const cleaned = filePath
    .replace(/\\/g, '/')
    .replace(/^[A-Za-z]:/, '')
    .split('/')
    .filter((part) => part !== '' && part !== '.' && part !== '..')
    .join('/');
  const safeTarget = target.replace(/[^A-Za-z0-9_.-]/g, '_') || 'target';
  return `/${safeTarget}/${cleaned === '' ? 'output' : cleaned}`;
}

/** A list of strings of an answer, such as `errors` or `refused` of `iface.generate`. */
export function stringList(result: unknown, key: string): string[] {
  if (!isRecord(result)) {
    return [];
  }
  const value = result[key];
  return Array.isArray(value) ? value.filter((item): item is string => typeof item === 'string') : [];
}

/** A string field of an answer, such as `folder` of `iface.generate`. */
export function stringField(result: unknown, key: string): string | undefined {
  if (!isRecord(result)) {
    return undefined;
  }
  const value = result[key];
  return typeof value === 'string' && value !== '' ? value : undefined;
}
