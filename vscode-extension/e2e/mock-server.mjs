// A stand-in for `iface-lsp --stdio`, used by `npm run e2e -- --server=mock`
// to test the client inside real VS Code when the Python server is not
// installed. It speaks just enough LSP over stdio: diagnostics for the word
// `Quaternoin`, a hover naming the word under the cursor, a few completions
// and the four iface.* commands (iface.graph in json: one component per file). It appends every message it receives to
// $IFACE_MOCK_LOG (JSON lines) so the e2e can check what the client sent.

import { appendFileSync, readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';

const log = process.env.IFACE_MOCK_LOG;
const documents = new Map();
let buffer = Buffer.alloc(0);

function send(message) {
  const body = Buffer.from(JSON.stringify({ jsonrpc: '2.0', ...message }), 'utf8');
  process.stdout.write(`Content-Length: ${body.length}\r\n\r\n`);
  process.stdout.write(body);
}

function wordAt(text, line, character) {
  const row = text.split(/\r?\n/)[line] ?? '';
  let start = character;
  let end = character;
  while (start > 0 && /[\w.]/.test(row[start - 1])) start -= 1;
  while (end < row.length && /[\w.]/.test(row[end])) end += 1;
  return row.slice(start, end);
}

function publishDiagnostics(uri) {
  const text = documents.get(uri) ?? '';
  const diagnostics = [];
  text.split(/\r?\n/).forEach((row, line) => {
    const at = row.indexOf('Quaternoin');
    if (at >= 0) {
      diagnostics.push({
        range: { start: { line, character: at }, end: { line, character: at + 'Quaternoin'.length } },
        severity: 1,
        source: 'iface (mock)',
        message: "unknown type 'Quaternoin'",
      });
    }
  });
  send({ method: 'textDocument/publishDiagnostics', params: { uri, diagnostics } });
}

/** A graph of the files the client names: one component per file with a `component` line, linked in a chain. */
function mockGraph(uris) {
  const components = [];
  for (const uri of uris) {
    const file = fileURLToPath(uri);
    const lines = readFileSync(file, 'utf8').split('\n');
    const line = lines.findIndex((l) => l.startsWith('component '));
    if (line < 0) continue;
    const name = lines[line].split(/\s+/)[1];
    components.push({ id: name, name, version: null, file, at: { file, line: line + 1, column: 11 } });
  }
  const links = components.slice(1).map((c, i) => ({
    kind: 'topic', set: 'M', name: `/mock/${i}`, type: 'mock_msgs/Mock', to_type: 'mock_msgs/Other', from: components[i].id, to: c.id,
    qos_mismatch: [], type_conflict: true, from_at: components[i].at, to_at: c.at, definition: components[i].at,
  }));
  return { schema: 'iface-graph/1', components, links, open: [], checks: [] };
}

function handle(message) {
  if (log) appendFileSync(log, JSON.stringify(message) + '\n');
  const { id, method, params } = message;
  switch (method) {
    case 'initialize':
      send({
        id,
        result: {
          capabilities: {
            textDocumentSync: 1,
            hoverProvider: true,
            completionProvider: { triggerCharacters: ['.'] },
            documentFormattingProvider: true,
            executeCommandProvider: { commands: ['iface.generate', 'iface.preview', 'iface.compat', 'iface.graph'] },
          },
          serverInfo: { name: 'iface-lsp (mock)', version: '0' },
        },
      });
      return;
    case 'textDocument/didOpen':
      documents.set(params.textDocument.uri, params.textDocument.text);
      publishDiagnostics(params.textDocument.uri);
      return;
    case 'textDocument/didChange':
      documents.set(params.textDocument.uri, params.contentChanges.at(-1).text);
      publishDiagnostics(params.textDocument.uri);
      return;
    case 'textDocument/didClose':
      documents.delete(params.textDocument.uri);
      return;
    case 'textDocument/hover': {
      const word = wordAt(documents.get(params.textDocument.uri) ?? '', params.position.line, params.position.character);
      send({ id, result: word ? { contents: { kind: 'markdown', value: `**${word}** (mock hover)` } } : null });
      return;
    }
    case 'textDocument/completion':
      send({
        id,
        result: ['float64', 'i32', 'bool', 'string'].map((label) => ({ label, kind: 25, detail: 'builtin type (mock)' })),
      });
      return;
    case 'textDocument/formatting':
      send({ id, result: [] });
      return;
    case 'workspace/executeCommand': {
      const args = params.arguments?.[0] ?? {};
      const results = {
        'iface.generate': { files: [] },
        'iface.preview': { files: [{ path: 'msg/JointCommand.msg', text: 'float64[6] positions\n' }] },
        'iface.compat': `compatible: ${args.old} -> ${args.new}\n`,
        'iface.graph': args.format === 'json'
          ? { text: '{}', format: 'json', graph: mockGraph(args.uris ?? []) }
          : `graph LR\n  arm_controller -->|/arm/command| JointCommand\n%% ${(args.uris ?? []).length} files, ${args.format}\n`,
      };
      send({ id, result: results[params.command] ?? null });
      return;
    }
    case 'shutdown':
      send({ id, result: null });
      return;
    case 'exit':
      process.exit(0);
      return;
    default:
      if (id !== undefined && method !== undefined) {
        send({ id, error: { code: -32601, message: `unhandled ${method}` } });
      }
  }
}

process.stdin.on('data', (chunk) => {
  buffer = Buffer.concat([buffer, chunk]);
  for (;;) {
    const headerEnd = buffer.indexOf('\r\n\r\n');
    if (headerEnd < 0) return;
    const header = buffer.subarray(0, headerEnd).toString('ascii');
    const match = /Content-Length: *(\d+)/i.exec(header);
    if (!match) {
      buffer = buffer.subarray(headerEnd + 4);
      continue;
    }
    const length = Number(match[1]);
    if (buffer.length < headerEnd + 4 + length) return;
    const body = buffer.subarray(headerEnd + 4, headerEnd + 4 + length).toString('utf8');
    buffer = buffer.subarray(headerEnd + 4 + length);
    handle(JSON.parse(body));
  }
});
process.stdin.on('end', () => process.exit(0));
