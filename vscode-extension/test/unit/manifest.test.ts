// Checks of the package itself: pinned versions, packaging metadata,
// contributions that match the code, and grammar tests that cover the language.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, readFileSync, readdirSync } from 'node:fs';
import { join } from 'node:path';
import { describe, it } from 'node:test';

const root = join(__dirname, '..', '..');
const read = (file: string): string => readFileSync(join(root, file), 'utf8');
const json = (file: string): unknown => JSON.parse(read(file)) as unknown;

interface Manifest {
  version: string;
  license?: string;
  repository?: { url?: string };
  engines: { vscode: string };
  main: string;
  dependencies: Record<string, string>;
  devDependencies: Record<string, string>;
  contributes: {
    commands: { command: string; title: string; category?: string }[];
    configuration: { properties: Record<string, { default?: unknown }> };
    languages: { id: string; extensions: string[]; configuration: string }[];
    grammars: { language: string; scopeName: string; path: string }[];
    snippets: { language: string; path: string }[];
  };
}

const manifest = json('package.json') as Manifest;

export const KEYWORDS = [
  'include', 'cpp_include', 'namespace', 'component', 'version', 'external', 'publishes', 'subscribes',
  'provides', 'calls', 'on', 'const', 'typedef', 'enum', 'senum', 'struct', 'union', 'exception', 'message',
  'configuration', 'state', 'service', 'extends', 'action', 'oneway', 'void', 'throws', 'required', 'optional',
  'xsd_all', 'map', 'set', 'list', 'cpp_type', 'system', 'instance',
];
export const BUILTIN_TYPES = [
  'bool', 'byte', 'i8', 'i16', 'i32', 'i64', 'double', 'binary', 'uuid', 'u8', 'u16', 'u32', 'u64', 'int8',
  'int16', 'int32', 'int64', 'uint8', 'uint16', 'uint32', 'uint64', 'float', 'float32', 'float64', 'char',
  'wchar', 'octet', 'string', 'wstring',
];
const SECTIONS = ['request', 'response', 'goal', 'result', 'feedback'];

describe('package.json', () => {
  it('pins every dependency to an exact version', () => {
    const all = { ...manifest.dependencies, ...manifest.devDependencies };
    assert.ok(Object.keys(all).length > 0);
    for (const [name, version] of Object.entries(all)) {
      assert.match(version, /^\d+\.\d+\.\d+$/, `${name}@${version} is not an exact version`);
    }
  });

  it('has a lockfile that matches it', () => {
    const lock = json('package-lock.json') as {
      lockfileVersion: number;
      packages: Record<string, { version?: string; dependencies?: Record<string, string>; devDependencies?: Record<string, string> }>;
    };
    assert.equal(lock.lockfileVersion, 3);
    const rootPackage = lock.packages[''];
    assert.ok(rootPackage !== undefined);
    assert.deepEqual(rootPackage.dependencies, manifest.dependencies);
    assert.deepEqual(rootPackage.devDependencies, manifest.devDependencies);
    for (const [name, version] of Object.entries({ ...manifest.dependencies, ...manifest.devDependencies })) {
      assert.equal(lock.packages[`node_modules/${name}`]?.version, version, `lockfile has another ${name}`);
    }
  });

  it('has the packaging metadata vsce wants', () => {
    assert.equal(manifest.license, 'MIT');
    assert.match(read('LICENSE'), /MIT License/);
    assert.ok(manifest.repository?.url !== undefined && manifest.repository.url !== '');
    assert.match(manifest.engines.vscode, /^(\^|>=)?\d+\.\d+\.\d+$/);
    assert.equal(manifest.main, './dist/extension.js');
    assert.ok(existsSync(join(root, 'README.md')));
  });

  it('contributes exactly the commands that the extension registers', () => {
    const source = read('src/extension.ts');
    const registered = [...source.matchAll(/registerCommand\('([^']+)'/g)].map((m) => m[1]).sort();
    const contributed = manifest.contributes.commands.map((c) => c.command).sort();
    assert.deepEqual(contributed, registered);
    const titles = manifest.contributes.commands.map((c) => c.title);
    for (const title of ['Generate for target…', 'Preview generated files', 'Check compatibility against…', 'Show system graph', 'Restart server']) {
      assert.ok(titles.includes(title), `missing command ${title}`);
    }
    // The server's own executeCommand ids are registered by vscode-languageclient: no clash.
    for (const serverCommand of ['iface.generate', 'iface.preview', 'iface.compat', 'iface.graph']) {
      assert.ok(!contributed.includes(serverCommand), `${serverCommand} would clash with the server's command`);
      assert.ok(source.includes(`'${serverCommand}'`), `${serverCommand} is never called`);
    }
  });

  it('contributes the settings that mirror the server', () => {
    const properties = Object.keys(manifest.contributes.configuration.properties);
    for (const key of ['iface.server.path', 'iface.server.args', 'iface.output.folder', 'iface.targets', 'iface.includePaths', 'iface.compat.baseline']) {
      assert.ok(properties.includes(key), `missing setting ${key}`);
    }
    assert.deepEqual(manifest.contributes.configuration.properties['iface.server.args']?.default, ['--stdio']);
  });
});

describe('language files', () => {
  it('registers the language, grammar and snippets', () => {
    const language = manifest.contributes.languages[0];
    assert.equal(language?.id, 'iface');
    assert.deepEqual(language?.extensions, ['.iface']);
    assert.equal(manifest.contributes.grammars[0]?.scopeName, 'source.iface');
    for (const file of [language?.configuration, manifest.contributes.grammars[0]?.path, manifest.contributes.snippets[0]?.path]) {
      assert.ok(file !== undefined && existsSync(join(root, file)), `${String(file)} is missing`);
    }
  });

  it('has a language configuration with comments, brackets, auto-closing, folding and indentation', () => {
    const config = json('language-configuration.json') as Record<string, unknown>;
    for (const key of ['comments', 'brackets', 'autoClosingPairs', 'surroundingPairs', 'folding', 'indentationRules', 'onEnterRules']) {
      assert.ok(key in config, `language-configuration.json has no ${key}`);
    }
  });

  it('has a snippet for each block', () => {
    const snippets = json('snippets/iface.code-snippets') as Record<string, { prefix: string; body: string[] }>;
    const prefixes = Object.values(snippets).map((s) => s.prefix);
    for (const block of ['component', 'namespace', 'include', 'external', 'message', 'struct', 'union', 'exception', 'configuration', 'state', 'enum', 'senum', 'typedef', 'const', 'service', 'action', 'publishes', 'subscribes', 'provides', 'calls', ...SECTIONS]) {
      assert.ok(prefixes.includes(block), `no snippet for ${block}`);
    }
    for (const snippet of Object.values(snippets)) {
      assert.ok(Array.isArray(snippet.body) && snippet.body.every((line) => typeof line === 'string'));
    }
  });

  it('keeps syntaxes/iface.tmLanguage.json generated from scripts/grammar.mjs', () => {
    execFileSync(process.execPath, [join(root, 'scripts', 'grammar.mjs'), '--check'], { stdio: 'pipe' });
  });

  it('has grammar tests for every keyword, builtin type and section name', () => {
    const dir = join(root, 'test', 'grammar');
    const lines = readdirSync(dir)
      .filter((f) => f.endsWith('.iface'))
      .flatMap((f) => readFileSync(join(dir, f), 'utf8').split('\n'));
    const source = lines.filter((l) => !l.trimStart().startsWith('//')).join('\n');
    const assertions = lines.filter((l) => /^\s*\/\/\s*(\^|<-)/.test(l)).join('\n');
    for (const word of [...KEYWORDS, ...BUILTIN_TYPES, ...SECTIONS]) {
      assert.match(source, new RegExp(`(?<![\\w.])${word}(?![\\w.])`), `no grammar test uses ${word}`);
    }
    for (const scope of ['comment.line.double-slash', 'comment.line.number-sign', 'comment.block.iface', 'comment.block.documentation',
      'string.quoted.double', 'string.quoted.single', 'constant.numeric.integer.decimal', 'constant.numeric.integer.hexadecimal',
      'constant.numeric.float', 'entity.other.attribute-name', 'support.type.primitive', 'variable.other.field']) {
      assert.ok(assertions.includes(scope), `no grammar test asserts ${scope}`);
    }
  });
});
