// Bundles the extension, the graph panel's script and the unit tests with esbuild into dist/.
import { build } from 'esbuild';
import { readdirSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const production = process.argv.includes('--production');

const common = {
  bundle: true,
  platform: 'node',
  format: 'cjs',
  // VS Code 1.82 runs extensions on Node 18.
  target: 'node18',
  sourcemap: !production,
  logLevel: 'warning',
  absWorkingDir: root,
};

await build({
  ...common,
  entryPoints: ['src/extension.ts'],
  outfile: 'dist/extension.js',
  external: ['vscode'],
  minify: production,
});

// The script of the system-graph webview: a browser bundle (dagre included), no Node APIs.
await build({
  ...common,
  platform: 'browser',
  format: 'iife',
  target: 'es2020',
  entryPoints: ['src/graph/webview.ts'],
  outfile: 'dist/webview/graph.js',
  minify: production,
});

const tests = readdirSync(join(root, 'test', 'unit'))
  .filter((name) => name.endsWith('.test.ts'))
  .map((name) => `test/unit/${name}`);
await build({
  ...common,
  entryPoints: tests,
  outdir: 'dist/test',
  external: ['vscode', 'esbuild'],
  sourcemap: true,
});
console.log(`bundled dist/extension.js, dist/webview/graph.js and ${tests.length} unit test file(s)`);
