// The settings that the language server reads. No `vscode` import here.
//
// They are sent as `initializationOptions` on start and, whenever they change,
// as `workspace/didChangeConfiguration` with `{ settings: { iface: ... } }`.
// The shape mirrors the `iface.*` settings of package.json.

export interface IfaceSettings {
  output: { folder: string };
  targets: string[];
  includePaths: string[];
  compat: { baseline: string };
}

export interface ServerLaunchSettings {
  path: string;
  args: string[];
}

/** Reads one setting; `undefined` when unset. */
export type SettingReader = (key: string) => unknown;

function asString(value: unknown, fallback: string): string {
  return typeof value === 'string' ? value : fallback;
}

function asStringArray(value: unknown, fallback: string[]): string[] {
  if (!Array.isArray(value)) {
    return fallback;
  }
  return value.filter((item): item is string => typeof item === 'string');
}

export function readServerSettings(get: SettingReader): IfaceSettings {
  return {
    output: { folder: asString(get('output.folder'), '') },
    targets: asStringArray(get('targets'), []),
    includePaths: asStringArray(get('includePaths'), []),
    compat: { baseline: asString(get('compat.baseline'), '') },
  };
}

export function readLaunchSettings(get: SettingReader): ServerLaunchSettings {
  return {
    path: asString(get('server.path'), ''),
    args: asStringArray(get('server.args'), ['--stdio']),
  };
}

/** The `workspace/didChangeConfiguration` parameters. */
export function didChangeConfigurationParams(settings: IfaceSettings): { settings: { iface: IfaceSettings } } {
  return { settings: { iface: settings } };
}
