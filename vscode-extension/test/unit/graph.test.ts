// The system-graph panel without VS Code: the server's data, the drawing, the page and its CSP.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { describe, it } from 'node:test';

import { type GraphData, isConflict, knownFiles, parseGraph, parseLocation, utf16Column } from '../../src/graph/data';
import { type SvgChild, type SvgElement, approximateMeasure, drawGraph, linkType, smoothPath, toSvgText } from '../../src/graph/draw';
import { contentSecurityPolicy, graphPage, makeNonce } from '../../src/graph/html';

// `iface-lsp graph` of tests/compat/data/system/*.iface (tests/test_vscode_extension.py keeps it current)
const fixture = JSON.parse(readFileSync(join(__dirname, '..', '..', 'test', 'unit', 'fixtures', 'system-graph.json'), 'utf8')) as unknown;

function graph(): GraphData {
  const data = parseGraph({ text: '', graph: fixture });
  assert.ok(data !== undefined);
  return data;
}

function all(node: SvgChild, out: SvgElement[] = []): SvgElement[] {
  if (typeof node !== 'string') {
    out.push(node);
    node.children.forEach((c) => all(c, out));
  }
  return out;
}

function classed(root: SvgElement, cls: string): SvgElement[] {
  return all(root).filter((e) => (e.attrs['class'] ?? '').split(' ').includes(cls));
}

function text(node: SvgChild): string {
  return typeof node === 'string' ? node : node.children.map(text).join(' ');
}

function rect(g: SvgElement): { x: number; y: number; w: number; h: number } {
  const r = g.children.find((c): c is SvgElement => typeof c !== 'string' && c.tag === 'rect');
  assert.ok(r !== undefined);
  return { x: Number(r.attrs['x']), y: Number(r.attrs['y']), w: Number(r.attrs['width']), h: Number(r.attrs['height']) };
}

describe('graph data', () => {
  it('reads the server answer, from `graph` or from the JSON text', () => {
    const data = graph();
    assert.deepEqual(data.components.map((c) => c.name), ['camera', 'detector', 'logger']);
    assert.equal(data.links.length, 2);
    assert.deepEqual(parseGraph({ text: JSON.stringify(fixture) }), data);
    assert.equal(parseGraph({ text: 'flowchart LR' }), undefined);
    assert.equal(parseGraph({ graph: { schema: 'other/1' } }), undefined);
    assert.equal(parseGraph(null), undefined);
  });

  it('marks conflicts: types that differ, QoS that cannot match', () => {
    const byName = new Map(graph().links.map((l) => [l.name, l]));
    const detections = byName.get('/detections');
    const image = byName.get('/image');
    assert.ok(detections !== undefined && image !== undefined);
    assert.ok(isConflict(detections) && detections.typeConflict?.includes('several types'));
    assert.deepEqual([detections.type, detections.toType], ['vision_msgs/Detections', 'vision_msgs/Boxes']);
    assert.ok(isConflict(image) && image.typeConflict === null && image.qosMismatch.length === 2);
  });

  it('drops what it cannot use instead of failing', () => {
    const data = parseGraph({
      graph: {
        schema: 'iface-graph/1',
        components: [{ id: 'a', name: 'a', at: { file: '/w/a.iface', line: 0, column: 1 } }, { id: 'a' }, 'x'],
        links: [{ from: 'a', to: 'missing' }, { from: 'a', to: 'a', name: '/loop', qos_mismatch: [1, 'q'], type_conflict: true }],
        open: [{ component: 'nobody' }],
        checks: [{ file: '/w/a.iface', line: 2, column: 1, severity: 'error', code: 'c', message: 'm' }, { line: 2 }],
      },
    });
    assert.ok(data !== undefined);
    assert.equal(data.components.length, 1);
    assert.equal(data.components[0]?.location, null); // line 0 is not a line
    assert.deepEqual(data.links.map((l) => [l.name, l.qosMismatch, l.typeConflict]), [['/loop', ['q'], 'the two ends use different types']]);
    assert.equal(data.open.length, 0);
    assert.equal(data.checks.length, 1);
    assert.deepEqual(parseLocation({ file: '/f', line: 3, column: 2 }), { file: '/f', line: 3, column: 2 });
    assert.equal(parseLocation({ file: '', line: 3, column: 2 }), null);
  });

  it('knows the files it may open', () => {
    const files = knownFiles(graph());
    assert.deepEqual([...files].map((f) => f.split('/').pop()).sort(), ['camera.iface', 'detector.iface', 'logger.iface']);
  });

  it('converts code-point columns to UTF-16', () => {
    assert.equal(utf16Column('abc', 2), 2);
    assert.equal(utf16Column('😀x', 1), 2);
    assert.equal(utf16Column('😀x', 5), 3);
  });
});

describe('drawing', () => {
  it('draws every component as a box that goes to its declaration', () => {
    const data = graph();
    const drawing = drawGraph(data);
    const boxes = classed(drawing.root, 'component');
    assert.deepEqual(boxes.map((b) => b.attrs['data-id']), ['camera', 'detector', 'logger']);
    for (const [i, box] of boxes.entries()) {
      const target = drawing.targets[Number(box.attrs['data-target'])];
      assert.deepEqual(target, data.components[i]?.location);
      assert.equal(box.attrs['role'], 'button');
      assert.equal(box.attrs['tabindex'], '0');
      assert.match(text(box), new RegExp(data.components[i]?.name ?? '-'));
    }
  });

  it('draws links with their names and types, conflicts in red, and open ends as stubs', () => {
    const drawing = drawGraph(graph());
    const edges = classed(drawing.root, 'edge');
    assert.equal(edges.length, 4); // two links, two stubs
    const conflicts = edges.filter((e) => (e.attrs['class'] ?? '').includes('conflict'));
    assert.equal(conflicts.length, 2);
    for (const e of conflicts) {
      const line = e.children.find((c): c is SvgElement => typeof c !== 'string' && c.attrs['class'] === 'line');
      assert.equal(line?.attrs['marker-end'], 'url(#arrow-conflict)');
    }
    const labels = classed(drawing.root, 'label').map(text);
    assert.ok(labels.some((t) => t.includes('/detections') && t.includes('vision_msgs/Detections ≠ vision_msgs/Boxes')), labels.join(' | '));
    assert.ok(labels.some((t) => t.includes('/image') && t.includes('vision_msgs/Image')));
    const stubs = classed(drawing.root, 'stub').map((s) => s.attrs['class']);
    assert.deepEqual(stubs.sort(), ['stub warning', 'stub warning']);
    assert.equal(drawing.summary, '3 components · 2 links · 3 errors · 2 warnings');
    // a link goes to the definition of its type
    const detections = edges.find((e) => text(e).includes('/detections'));
    const target = drawing.targets[Number(detections?.attrs['data-target'])];
    assert.ok(target !== undefined && target.file.endsWith('detector.iface') && target.line === 13);
  });

  it('labels a link with both types when its ends disagree', () => {
    const link = graph().links.find((l) => l.name === '/detections');
    assert.ok(link !== undefined);
    assert.equal(linkType(link), 'vision_msgs/Detections ≠ vision_msgs/Boxes');
    assert.equal(linkType({ ...link, toType: link.type }), 'vision_msgs/Detections — types differ'); // same name, other fields
    assert.equal(linkType({ ...link, kind: 'service', toType: link.type, typeConflict: null }), 'vision_msgs/Detections (service)');
    assert.equal(linkType({ ...link, kind: 'service', set: 'Δ', toType: link.type, typeConflict: null }), 'vision_msgs/Detections (diagnostics)');
  });

  it('keeps boxes and labels apart and inside the picture', () => {
    const drawing = drawGraph(graph());
    const shapes = [...classed(drawing.root, 'component'), ...classed(drawing.root, 'stub'), ...classed(drawing.root, 'label')].map(rect);
    for (const [i, a] of shapes.entries()) {
      assert.ok(a.x >= 0 && a.y >= 0 && a.x + a.w <= drawing.width + 0.5 && a.y + a.h <= drawing.height + 0.5);
      for (const b of shapes.slice(i + 1)) {
        const apart = a.x + a.w <= b.x + 0.5 || b.x + b.w <= a.x + 0.5 || a.y + a.h <= b.y + 0.5 || b.y + b.h <= a.y + 0.5;
        assert.ok(apart, `${JSON.stringify(a)} overlaps ${JSON.stringify(b)}`);
      }
    }
  });

  it('puts text in text nodes only, so names cannot become markup', () => {
    const evil = '/x"><script>alert(1)</script>';
    const data: GraphData = {
      components: [{ id: 'a', name: '<b>a</b>', version: null, file: '/w/a.iface', location: { file: '/w/a.iface', line: 1, column: 1 } }],
      links: [{
        kind: 'topic', set: 'M', name: evil, type: 'T', toType: 'T', from: 'a', to: 'a', qosMismatch: [], typeConflict: null,
        fromLocation: null, toLocation: null, definition: null,
      }],
      open: [],
      checks: [],
    };
    const drawing = drawGraph(data);
    assert.ok(all(drawing.root).every((e) => ['svg', 'defs', 'marker', 'path', 'g', 'rect', 'text', 'title'].includes(e.tag)));
    const svg = toSvgText(drawing.root);
    assert.ok(!svg.includes('<script') && !svg.includes('<b>'));
    assert.ok(svg.includes('&lt;script&gt;'));
  });

  it('draws an empty graph and a lone component', () => {
    assert.equal(classed(drawGraph({ components: [], links: [], open: [], checks: [] }).root, 'component').length, 0);
    const one = drawGraph({ components: [{ id: 'a', name: 'a', version: '1', file: 'a.iface', location: null }], links: [], open: [], checks: [] });
    assert.equal(classed(one.root, 'component').length, 1);
    assert.equal(one.targets.length, 0);
  });

  it('sizes boxes by the measured text', () => {
    const data = graph();
    const wide = drawGraph(data, (t, k) => approximateMeasure(t, k) * 3);
    const narrow = drawGraph(data);
    assert.ok(rect(classed(wide.root, 'component')[1] as SvgElement).w > rect(classed(narrow.root, 'component')[1] as SvgElement).w);
  });

  it('makes smooth paths through the points', () => {
    assert.equal(smoothPath([]), '');
    assert.equal(smoothPath([{ x: 0, y: 0 }, { x: 10, y: 0 }]), 'M0,0 C1.7,0 8.3,0 10,0');
  });
});

describe('the panel page', () => {
  const resources = { cspSource: 'https://x.vscode-cdn.net', scriptUri: 'https://x.vscode-cdn.net/graph.js', styleUri: 'https://x.vscode-cdn.net/graph.css', nonce: 'abc123' };

  it('allows only the extension script (by nonce) and style sheet, nothing from the network', () => {
    const csp = contentSecurityPolicy(resources);
    assert.match(csp, /^default-src 'none'/);
    assert.ok(csp.includes("script-src 'nonce-abc123'"));
    assert.ok(csp.includes('style-src https://x.vscode-cdn.net'));
    assert.ok(!csp.includes('unsafe'));
    const page = graphPage(resources);
    assert.ok(page.includes(`content="${csp.replace(/'/g, "'")}"`));
    const scripts = [...page.matchAll(/<script\b[^>]*>/g)].map((m) => m[0]);
    assert.deepEqual(scripts, ['<script nonce="abc123" src="https://x.vscode-cdn.net/graph.js">']);
    assert.ok(!/\sstyle=|\son[a-z]+=|<style/i.test(page), 'inline style or handlers');
    assert.ok(!/https?:\/\/(?!x\.vscode-cdn\.net)/.test(page), 'a resource from elsewhere');
  });

  it('makes unguessable nonces', () => {
    const nonce = makeNonce((n) => Uint8Array.from({ length: n }, (_, i) => i * 7));
    assert.match(nonce, /^[A-Za-z0-9]{32}$/);
  });
});
