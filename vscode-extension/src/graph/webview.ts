// The script of the system-graph panel (runs in the webview, bundled by esbuild
// into dist/webview/graph.js). It draws what the extension posts, and posts back
// which location to open when an element is clicked or activated with the
// keyboard. No inline script or style: the page's CSP allows this file only.

import type { Check, GraphData, Location } from './data';
import { type Drawing, FONT_SIZE, type Measure, type SvgChild, type TextKind, approximateMeasure, drawGraph } from './draw';

interface VsCodeApi {
  postMessage(message: unknown): void;
  getState(): unknown;
  setState(state: unknown): void;
}
declare function acquireVsCodeApi(): VsCodeApi;

type Incoming =
  | { type: 'graph'; data: GraphData; generated: string }
  | { type: 'loading' }
  | { type: 'error'; message: string };

interface State {
  data: GraphData;
  generated: string;
  zoom: number | 'fit';
}

const vscode = acquireVsCodeApi();
const SVG_NS = 'http://www.w3.org/2000/svg';
const view = document.getElementById('graph') as HTMLDivElement;
const status = document.getElementById('status') as HTMLSpanElement;
const checksList = document.getElementById('checks') as HTMLUListElement;
let drawing: Drawing | undefined;
let state: State | undefined;

function canvasMeasure(): Measure {
  const canvas = document.createElement('canvas');
  const context = canvas.getContext('2d');
  if (context === null) {
    return approximateMeasure;
  }
  const family = getComputedStyle(document.body).fontFamily || 'sans-serif';
  return (text: string, kind: TextKind) => {
    context.font = `${kind === 'title' ? 'bold ' : ''}${FONT_SIZE[kind]}px ${family}`;
    // a little more than measured: the SVG text may fall back to a wider face
    return context.measureText(text).width * 1.04;
  };
}

function materialize(node: SvgChild): Node {
  if (typeof node === 'string') {
    return document.createTextNode(node);
  }
  const element = document.createElementNS(SVG_NS, node.tag);
  for (const [key, value] of Object.entries(node.attrs)) {
    if (key !== 'xmlns') {
      element.setAttribute(key, value);
    }
  }
  for (const child of node.children) {
    element.appendChild(materialize(child));
  }
  return element;
}

function open(location: Location | undefined): void {
  if (location !== undefined) {
    vscode.postMessage({ type: 'open', file: location.file, line: location.line, column: location.column });
  }
}

function applyZoom(): void {
  const svg = view.querySelector('svg');
  if (svg === null || drawing === undefined || state === undefined) {
    return;
  }
  if (state.zoom === 'fit') {
    // as large as fits, never larger than life, and not so small that the text cannot be read (then scroll)
    const scale = Math.max(0.8, Math.min(1, (view.clientWidth - 8) / drawing.width, (view.clientHeight - 8) / drawing.height));
    svg.setAttribute('width', String(Math.max(1, drawing.width * scale)));
    svg.setAttribute('height', String(Math.max(1, drawing.height * scale)));
  } else {
    svg.setAttribute('width', String(drawing.width * state.zoom));
    svg.setAttribute('height', String(drawing.height * state.zoom));
  }
  document.body.dataset['zoom'] = String(state.zoom);
}

function checkItem(check: Check): HTMLLIElement {
  const item = document.createElement('li');
  item.className = `check ${check.severity}`;
  const badge = document.createElement('span');
  badge.className = 'severity';
  badge.textContent = check.severity;
  const message = document.createElement('span');
  message.className = 'message';
  message.textContent = ` ${check.message} `;
  const link = document.createElement('a');
  link.href = '#';
  link.textContent = `${check.location.file.split(/[\\/]/).pop() ?? check.location.file}:${check.location.line}`;
  link.title = check.location.file;
  link.addEventListener('click', (event) => {
    event.preventDefault();
    open(check.location);
  });
  item.append(badge, message, link);
  return item;
}

function render(next: State): void {
  state = next;
  vscode.setState(next);
  const { data } = next;
  view.replaceChildren();
  checksList.replaceChildren();
  document.body.classList.remove('loading');
  if (data.components.length === 0) {
    drawing = undefined;
    const empty = document.createElement('p');
    empty.className = 'empty';
    empty.textContent = 'No component in this workspace: a file needs a `component` declaration to appear in the graph.';
    view.append(empty);
    status.textContent = 'no components';
    document.body.dataset['rendered'] = 'empty';
    return;
  }
  drawing = drawGraph(data, canvasMeasure());
  view.append(materialize(drawing.root));
  status.textContent = `${drawing.summary} · ${next.generated}`;
  checksList.append(...data.checks.map(checkItem));
  applyZoom();
  document.body.dataset['rendered'] = String(data.components.length);
}

function targetOf(event: Event): Location | undefined {
  const element = (event.target as Element | null)?.closest('[data-target]');
  const index = Number(element?.getAttribute('data-target'));
  return drawing !== undefined && Number.isInteger(index) ? drawing.targets[index] : undefined;
}

view.addEventListener('click', (event) => open(targetOf(event)));
view.addEventListener('keydown', (event) => {
  if (event.key === 'Enter' || event.key === ' ') {
    const location = targetOf(event);
    if (location !== undefined) {
      event.preventDefault();
      open(location);
    }
  }
});

function setZoom(zoom: number | 'fit'): void {
  if (state !== undefined) {
    state = { ...state, zoom };
    vscode.setState(state);
    applyZoom();
  }
}

function step(factor: number): void {
  if (state === undefined || drawing === undefined) {
    return;
  }
  const svg = view.querySelector('svg');
  const current = state.zoom === 'fit' ? Number(svg?.getAttribute('width') ?? drawing.width) / drawing.width : state.zoom;
  setZoom(Math.min(4, Math.max(0.1, current * factor)));
}

document.getElementById('refresh')?.addEventListener('click', () => vscode.postMessage({ type: 'refresh' }));
document.getElementById('zoom-in')?.addEventListener('click', () => step(1.25));
document.getElementById('zoom-out')?.addEventListener('click', () => step(0.8));
document.getElementById('zoom-fit')?.addEventListener('click', () => setZoom('fit'));
document.getElementById('zoom-actual')?.addEventListener('click', () => setZoom(1));
window.addEventListener('resize', () => applyZoom());

window.addEventListener('message', (event: MessageEvent<Incoming>) => {
  const message = event.data;
  if (message.type === 'graph') {
    render({ data: message.data, generated: message.generated, zoom: state?.zoom ?? 'fit' });
  } else if (message.type === 'loading') {
    document.body.classList.add('loading');
    status.textContent = 'building the graph…';
  } else if (message.type === 'error') {
    document.body.classList.remove('loading');
    status.textContent = message.message;
    document.body.dataset['rendered'] = 'error';
  }
});

const saved = vscode.getState() as State | undefined;
if (saved !== undefined && saved !== null && typeof saved === 'object' && 'data' in saved) {
  render(saved);
}
vscode.postMessage({ type: 'ready' });
