// The system graph as the server answers `iface.graph` with format `json`
// (`{ text, graph }`, schema `iface-graph/1`; see docs/compat.md). Shapes are
// checked here so that a surprise shows as a message, not as an exception in
// the panel. No `vscode` and no DOM here: the extension and the webview share it.

export interface Location {
  file: string;
  line: number;
  column: number;
}

export interface Component {
  id: string;
  name: string;
  version: string | null;
  file: string;
  location: Location | null;
}

export interface Link {
  kind: string;
  /** The set of the receiving end: M, S, A or Δ (a call of a diagnostics service). */
  set: string;
  name: string;
  type: string;
  toType: string;
  from: string;
  to: string;
  qosMismatch: string[];
  /** The message of the type-conflict check on this topic or name; null when the types agree. */
  typeConflict: string | null;
  fromLocation: Location | null;
  toLocation: Location | null;
  definition: Location | null;
}

export interface OpenEnd {
  component: string;
  kind: string;
  role: string;
  name: string;
  type: string;
  check: string;
  severity: string;
  location: Location | null;
  definition: Location | null;
}

export interface Check {
  severity: string;
  code: string;
  message: string;
  location: Location;
}

export interface GraphData {
  components: Component[];
  links: Link[];
  open: OpenEnd[];
  checks: Check[];
}

type Json = Record<string, unknown>;

function isRecord(value: unknown): value is Json {
  return typeof value === 'object' && value !== null && !Array.isArray(value);
}

function str(value: unknown, fallback = ''): string {
  return typeof value === 'string' ? value : fallback;
}

function strings(value: unknown): string[] {
  return Array.isArray(value) ? value.filter((v): v is string => typeof v === 'string') : [];
}

/** A `{file, line, column}` object; null when absent or malformed. */
export function parseLocation(value: unknown): Location | null {
  if (!isRecord(value)) {
    return null;
  }
  const { file, line, column } = value;
  if (typeof file !== 'string' || file === '' || typeof line !== 'number' || typeof column !== 'number') {
    return null;
  }
  if (!Number.isInteger(line) || !Number.isInteger(column) || line < 1 || column < 1) {
    return null;
  }
  return { file, line, column };
}

function records(value: unknown): Json[] {
  return Array.isArray(value) ? value.filter(isRecord) : [];
}

/**
 * The graph of an `iface.graph` answer: its `graph` member (absolute paths), or
 * the JSON in its `text`. Undefined when neither is an `iface-graph/1` graph.
 */
export function parseGraph(answer: unknown): GraphData | undefined {
  let raw: unknown = isRecord(answer) ? answer['graph'] : undefined;
  if (!isRecord(raw) && isRecord(answer) && typeof answer['text'] === 'string') {
    try {
      raw = JSON.parse(answer['text']) as unknown;
    } catch {
      raw = undefined;
    }
  }
  if (!isRecord(raw) || raw['schema'] !== 'iface-graph/1') {
    return undefined;
  }
  const components: Component[] = [];
  for (const c of records(raw['components'])) {
    const id = str(c['id']);
    if (id === '' || components.some((known) => known.id === id)) {
      continue;
    }
    components.push({
      id,
      name: str(c['name'], id),
      version: typeof c['version'] === 'string' ? c['version'] : null,
      file: str(c['file']),
      location: parseLocation(c['at']),
    });
  }
  const ids = new Set(components.map((c) => c.id));
  const checks: Check[] = [];
  for (const c of records(raw['checks'])) {
    const location = parseLocation(c);
    if (location !== null) {
      checks.push({ severity: str(c['severity'], 'information'), code: str(c['code']), message: str(c['message']), location });
    }
  }
  const links: Link[] = records(raw['links'])
    .filter((l) => ids.has(str(l['from'])) && ids.has(str(l['to'])))
    .map((l) => {
      const name = str(l['name']);
      const conflict = l['type_conflict'] === true || (typeof l['type_conflict'] === 'string' && l['type_conflict'] !== '');
      return {
        kind: str(l['kind'], 'topic'),
        set: str(l['set']),
        name,
        type: str(l['type'], '?'),
        toType: str(l['to_type'], str(l['type'], '?')),
        from: str(l['from']),
        to: str(l['to']),
        qosMismatch: strings(l['qos_mismatch']),
        typeConflict: conflict
          ? checks.find((c) => c.code.endsWith('-type-conflict') && c.message.includes(`'${name}'`))?.message ?? 'the two ends use different types'
          : null,
        fromLocation: parseLocation(l['from_at']),
        toLocation: parseLocation(l['to_at']),
        definition: parseLocation(l['definition']),
      };
    });
  const open: OpenEnd[] = records(raw['open'])
    .filter((p) => ids.has(str(p['component'])))
    .map((p) => ({
      component: str(p['component']),
      kind: str(p['kind'], 'topic'),
      role: str(p['role']),
      name: str(p['name']),
      type: str(p['type'], '?'),
      check: str(p['check']),
      severity: str(p['severity'], 'information'),
      location: parseLocation(p['at']),
      definition: parseLocation(p['definition']),
    }));
  return { components, links, open, checks };
}

/** True when a link is drawn in red: its two ends disagree on the type, or their QoS cannot match. */
export function isConflict(link: Link): boolean {
  return link.typeConflict !== null || link.qosMismatch.length > 0;
}

/** Every file a location of the graph points into (the panel opens no other). */
export function knownFiles(data: GraphData): Set<string> {
  const files = new Set<string>();
  const add = (l: Location | null): void => {
    if (l !== null) {
      files.add(l.file);
    }
  };
  data.components.forEach((c) => add(c.location));
  data.links.forEach((l) => [l.fromLocation, l.toLocation, l.definition].forEach(add));
  data.open.forEach((p) => [p.location, p.definition].forEach(add));
  data.checks.forEach((c) => add(c.location));
  return files;
}

/** The UTF-16 column of the `codePoints`-th code point of `text` (the server counts code points). */
export function utf16Column(text: string, codePoints: number): number {
  let column = 0;
  for (let seen = 0; seen < codePoints && column < text.length; seen += 1) {
    column += (text.codePointAt(column) ?? 0) > 0xffff ? 2 : 1;
  }
  return column;
}
