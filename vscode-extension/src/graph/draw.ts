// Draws the system graph: lays it out with dagre (bundled, nothing loaded from
// the network) and describes the SVG as a tree of plain objects. The webview
// turns the tree into DOM nodes with createElementNS/textContent, so no text
// of the graph is ever parsed as markup; the unit tests read the same tree.
// No `vscode` and no DOM here.

import dagre from '@dagrejs/dagre';

import { type GraphData, type Link, type Location, isConflict } from './data';

export interface SvgElement {
  tag: string;
  attrs: Record<string, string>;
  children: SvgChild[];
}
export type SvgChild = SvgElement | string;

/** Kinds of text, each with its own font (the webview measures them with a canvas). */
export type TextKind = 'title' | 'detail' | 'label';
export type Measure = (text: string, kind: TextKind) => number;

export const FONT_SIZE: Record<TextKind, number> = { title: 13, detail: 11, label: 11.5 };
const LINE = 1.35;

export interface Drawing {
  root: SvgElement;
  width: number;
  height: number;
  /** Where each clickable element goes: its `data-target` attribute is an index into this list. */
  targets: Location[];
  /** One line: how many components, links, errors and warnings. */
  summary: string;
}

/** A rough width for tests and as a fallback: 0.6 em per character. */
export const approximateMeasure: Measure = (text, kind) => text.length * FONT_SIZE[kind] * 0.6;

function el(tag: string, attrs: Record<string, string | number>, ...children: SvgChild[]): SvgElement {
  const out: Record<string, string> = {};
  for (const [key, value] of Object.entries(attrs)) {
    out[key] = typeof value === 'number' ? num(value) : value;
  }
  return { tag, attrs: out, children };
}

function num(v: number): string {
  const text = v.toFixed(1).replace(/\.0$/, '');
  return text === '-0' ? '0' : text;
}

interface Block {
  lines: { text: string; kind: TextKind; cls: string }[];
  width: number;
  height: number;
}

function block(measure: Measure, padX: number, padY: number, ...lines: { text: string; kind: TextKind; cls: string }[]): Block {
  const shown = lines.filter((l) => l.text !== '');
  const width = Math.max(0, ...shown.map((l) => measure(l.text, l.kind))) + 2 * padX;
  const height = shown.reduce((sum, l) => sum + FONT_SIZE[l.kind] * LINE, 0) + 2 * padY;
  return { lines: shown, width, height };
}

function texts(b: Block, cx: number, cy: number): SvgElement[] {
  const total = b.lines.reduce((sum, l) => sum + FONT_SIZE[l.kind] * LINE, 0);
  let y = cy - total / 2;
  return b.lines.map((l) => {
    y += FONT_SIZE[l.kind] * LINE;
    return el('text', { x: cx, y: y - FONT_SIZE[l.kind] * 0.32, 'text-anchor': 'middle', class: l.cls }, l.text);
  });
}

/** A smooth path through dagre's points (Catmull-Rom as cubic Béziers). */
export function smoothPath(points: { x: number; y: number }[]): string {
  if (points.length === 0) {
    return '';
  }
  const p = (i: number): { x: number; y: number } => points[Math.max(0, Math.min(points.length - 1, i))] ?? { x: 0, y: 0 };
  const parts = [`M${num(p(0).x)},${num(p(0).y)}`];
  for (let i = 0; i < points.length - 1; i += 1) {
    const [a, b, c, d] = [p(i - 1), p(i), p(i + 1), p(i + 2)];
    const c1 = { x: b.x + (c.x - a.x) / 6, y: b.y + (c.y - a.y) / 6 };
    const c2 = { x: c.x - (d.x - b.x) / 6, y: c.y - (d.y - b.y) / 6 };
    parts.push(`C${num(c1.x)},${num(c1.y)} ${num(c2.x)},${num(c2.y)} ${num(c.x)},${num(c.y)}`);
  }
  return parts.join(' ');
}

/** The type a link carries; both when its ends disagree (same name, other package or fields: "types differ"). */
export function linkType(link: Link): string {
  const shown = link.toType !== link.type ? `${link.type} ≠ ${link.toType}` : `${link.type}${link.typeConflict !== null ? ' — types differ' : ''}`;
  return link.kind === 'topic' ? shown : `${shown} (${link.set === 'Δ' ? 'diagnostics' : link.kind})`;
}

function where(l: Location | null): string {
  return l === null ? '' : `${l.file.split(/[\\/]/).pop() ?? l.file}:${l.line}`;
}

function plural(n: number, word: string): string {
  return `${n} ${word}${n === 1 ? '' : 's'}`;
}

/** Lays out and draws `data`; `measure` gives text widths in px. */
export function drawGraph(data: GraphData, measure: Measure = approximateMeasure): Drawing {
  const g = new dagre.graphlib.Graph({ multigraph: true });
  g.setGraph({ rankdir: 'LR', nodesep: 28, ranksep: 56, edgesep: 14, marginx: 16, marginy: 16 });
  g.setDefaultEdgeLabel(() => ({}));
  const names = new Map(data.components.map((c) => [c.id, c.name]));
  const blocks = new Map<string, Block>();
  for (const c of data.components) {
    const detail = [c.version !== null ? `v${c.version}` : '', c.file.split(/[\\/]/).pop() ?? ''].filter((x) => x !== '').join(' · ');
    const b = block(measure, 14, 9, { text: c.name, kind: 'title', cls: 'name' }, { text: detail, kind: 'detail', cls: 'detail' });
    blocks.set(`c:${c.id}`, b);
    g.setNode(`c:${c.id}`, { width: Math.max(b.width, 96), height: b.height });
  }
  data.open.forEach((p, i) => {
    const b = block(measure, 9, 5, { text: p.name, kind: 'label', cls: 'name' }, { text: p.type, kind: 'detail', cls: 'detail' });
    blocks.set(`o:${i}`, b);
    g.setNode(`o:${i}`, { width: b.width, height: b.height });
  });
  data.links.forEach((link, i) => {
    const b = block(measure, 7, 4, { text: link.name, kind: 'label', cls: 'name' }, { text: linkType(link), kind: 'detail', cls: 'detail' });
    blocks.set(`l:${i}`, b);
    g.setEdge(`c:${link.from}`, `c:${link.to}`, { width: b.width, height: b.height, labelpos: 'c' }, `l:${i}`);
  });
  data.open.forEach((p, i) => {
    const sends = p.role === 'publishes' || p.role === 'calls';
    const [v, w] = sends ? [`c:${p.component}`, `o:${i}`] : [`o:${i}`, `c:${p.component}`];
    g.setEdge(v, w, {}, `s:${i}`);
  });
  dagre.layout(g);

  const targets: Location[] = [];
  const target = (l: Location | null): Record<string, string> => {
    if (l === null) {
      return {};
    }
    targets.push(l);
    return { 'data-target': String(targets.length - 1), tabindex: '0', role: 'button' };
  };
  const edges: SvgElement[] = [];
  const labels: SvgElement[] = [];
  data.links.forEach((link, i) => {
    const e = g.edge({ v: `c:${link.from}`, w: `c:${link.to}`, name: `l:${i}` }) as { points?: { x: number; y: number }[]; x?: number; y?: number };
    const conflict = isConflict(link);
    const cls = `edge ${link.kind}${conflict ? ' conflict' : ''}`;
    const tip = [
      `${link.kind} ${link.name}: ${linkType(link)}`,
      `${names.get(link.from) ?? link.from} → ${names.get(link.to) ?? link.to}`,
      ...(link.typeConflict !== null ? [link.typeConflict] : []),
      ...link.qosMismatch.map((q) => `QoS: ${q}`),
      ...(link.definition !== null ? [`click: go to ${link.type} (${where(link.definition)})`] : []),
    ].join('\n');
    const goes = target(link.definition ?? link.fromLocation);
    edges.push(el('g', { class: cls, ...goes, 'aria-label': tip.split('\n')[0] ?? '' },
      el('title', {}, tip),
      el('path', { class: 'hit', d: smoothPath(e.points ?? []) }),
      el('path', { class: 'line', d: smoothPath(e.points ?? []), 'marker-end': `url(#${conflict ? 'arrow-conflict' : 'arrow'})` })));
    const b = blocks.get(`l:${i}`);
    if (b !== undefined && e.x !== undefined && e.y !== undefined) {
      labels.push(el('g', { class: `label${conflict ? ' conflict' : ''}`, ...(goes['data-target'] !== undefined ? { 'data-target': goes['data-target'] } : {}) },
        el('title', {}, tip),
        el('rect', { x: e.x - b.width / 2, y: e.y - b.height / 2, width: b.width, height: b.height, rx: 3 }),
        ...texts(b, e.x, e.y)));
    }
  });
  data.open.forEach((p, i) => {
    const sends = p.role === 'publishes' || p.role === 'calls';
    const [v, w] = sends ? [`c:${p.component}`, `o:${i}`] : [`o:${i}`, `c:${p.component}`];
    const e = g.edge({ v, w, name: `s:${i}` }) as { points?: { x: number; y: number }[] };
    edges.push(el('g', { class: `edge open ${p.kind}` }, el('path', { class: 'line', d: smoothPath(e.points ?? []), 'marker-end': 'url(#arrow)' })));
  });
  const nodes: SvgElement[] = [];
  for (const c of data.components) {
    const n = g.node(`c:${c.id}`) as { x: number; y: number; width: number; height: number };
    const b = blocks.get(`c:${c.id}`);
    const tip = `component ${c.name}${c.version !== null ? ` ${c.version}` : ''}\nclick: go to ${where(c.location)}`;
    nodes.push(el('g', { class: 'component', 'data-id': c.id, ...target(c.location), 'aria-label': `component ${c.name}` },
      el('title', {}, tip),
      el('rect', { x: n.x - n.width / 2, y: n.y - n.height / 2, width: n.width, height: n.height, rx: 5 }),
      ...(b !== undefined ? texts(b, n.x, n.y) : [])));
  }
  data.open.forEach((p, i) => {
    const n = g.node(`o:${i}`) as { x: number; y: number; width: number; height: number };
    const b = blocks.get(`o:${i}`);
    const owner = names.get(p.component) ?? p.component;
    const check = data.checks.find((c) => c.code === p.check && c.message.startsWith(owner) && c.message.includes(`'${p.name}'`))?.message ?? p.check;
    const tip = `${p.role} ${p.name}: ${p.type}\n${check}\nclick: go to ${where(p.location)}`;
    nodes.push(el('g', { class: `stub ${p.severity}`, ...target(p.location), 'aria-label': `${p.role} ${p.name}, no peer` },
      el('title', {}, tip),
      el('rect', { x: n.x - n.width / 2, y: n.y - n.height / 2, width: n.width, height: n.height, rx: 10 }),
      ...(b !== undefined ? texts(b, n.x, n.y) : [])));
  });
  const size = g.graph() as { width?: number; height?: number };
  const width = Math.max(size.width ?? 0, 1);
  const height = Math.max(size.height ?? 0, 1);
  const errors = data.checks.filter((c) => c.severity === 'error').length;
  const warnings = data.checks.filter((c) => c.severity === 'warning').length;
  const summary = [plural(data.components.length, 'component'), plural(data.links.length, 'link'), plural(errors, 'error'), plural(warnings, 'warning')].join(' · ');
  const marker = (id: string, cls: string): SvgElement => el('marker', {
    id, class: cls, viewBox: '0 0 10 10', refX: 9, refY: 5, markerWidth: 7, markerHeight: 7, orient: 'auto-start-reverse',
  }, el('path', { d: 'M0,0 L10,5 L0,10 z' }));
  const root = el('svg', {
    xmlns: 'http://www.w3.org/2000/svg', class: 'graph', viewBox: `0 0 ${num(width)} ${num(height)}`,
    width, height, role: 'group', 'aria-label': `System graph: ${summary}`,
  },
  el('defs', {}, marker('arrow', 'arrow'), marker('arrow-conflict', 'arrow conflict')),
  el('g', { class: 'edges' }, ...edges),
  el('g', { class: 'labels' }, ...labels),
  el('g', { class: 'nodes' }, ...nodes));
  return { root, width, height, targets, summary };
}

/** The tree as SVG text (for tests and for saving a picture). */
export function toSvgText(node: SvgChild): string {
  if (typeof node === 'string') {
    return node.replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;');
  }
  const attrs = Object.entries(node.attrs)
    .map(([k, v]) => ` ${k}="${v.replace(/&/g, '&amp;').replace(/"/g, '&quot;').replace(/</g, '&lt;')}"`)
    .join('');
  return `<${node.tag}${attrs}>${node.children.map(toSvgText).join('')}</${node.tag}>`;
}
