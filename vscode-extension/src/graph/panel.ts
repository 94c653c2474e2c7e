// The system-graph panel: a webview that draws the graph of the workspace's
// components (dist/webview/graph.js, built from webview.ts) and opens the
// definition of whatever is clicked in it. It refreshes itself when .iface
// files are saved, created or deleted while it is open.

import { randomBytes } from 'node:crypto';
import * as vscode from 'vscode';

import { type GraphData, knownFiles, utf16Column } from './data';
import { graphPage, makeNonce } from './html';

export const GRAPH_VIEW_TYPE = 'iface.graph';
const REFRESH_DELAY_MS = 400;

/** What the panel gets when it asks for the graph. */
export type GraphResult = { data: GraphData } | { error: string };

interface OpenMessage {
  type: 'open';
  file: string;
  line: number;
  column: number;
}

function isOpenMessage(value: unknown): value is OpenMessage {
  if (typeof value !== 'object' || value === null) {
    return false;
  }
  const m = value as Record<string, unknown>;
  return m['type'] === 'open' && typeof m['file'] === 'string' && Number.isInteger(m['line']) && Number.isInteger(m['column']);
}

export class GraphPanel implements vscode.Disposable {
  private panel: vscode.WebviewPanel | undefined;
  private latest: GraphData | undefined;
  private generated = '';
  private timer: ReturnType<typeof setTimeout> | undefined;
  private running: Promise<void> | undefined;
  private again = false;
  private readonly disposables: vscode.Disposable[] = [];

  constructor(
    private readonly extensionUri: vscode.Uri,
    private readonly fetchGraph: () => Promise<GraphResult>,
    private readonly log: (line: string) => void,
  ) {
    const watcher = vscode.workspace.createFileSystemWatcher('**/*.iface');
    this.disposables.push(
      watcher,
      watcher.onDidCreate(() => this.scheduleRefresh()),
      watcher.onDidDelete(() => this.scheduleRefresh()),
      vscode.workspace.onDidSaveTextDocument((doc) => {
        if (doc.languageId === 'iface' || doc.uri.path.endsWith('.iface')) {
          this.scheduleRefresh();
        }
      }),
      vscode.window.registerWebviewPanelSerializer(GRAPH_VIEW_TYPE, {
        deserializeWebviewPanel: async (panel: vscode.WebviewPanel) => {
          this.adopt(panel);
          await this.refresh();
        },
      }),
    );
  }

  /** Opens the panel (or brings it to the front) and draws the graph anew. */
  async show(): Promise<void> {
    if (this.panel !== undefined) {
      this.panel.reveal(undefined, false);
    } else {
      this.adopt(vscode.window.createWebviewPanel(GRAPH_VIEW_TYPE, 'System graph', { viewColumn: vscode.ViewColumn.Beside }, {}));
    }
    await this.refresh();
  }

  private adopt(panel: vscode.WebviewPanel): void {
    this.panel = panel;
    const roots = [vscode.Uri.joinPath(this.extensionUri, 'dist', 'webview'), vscode.Uri.joinPath(this.extensionUri, 'media')];
    panel.webview.options = { enableScripts: true, localResourceRoots: roots };
    panel.webview.html = graphPage({
      cspSource: panel.webview.cspSource,
      scriptUri: panel.webview.asWebviewUri(vscode.Uri.joinPath(this.extensionUri, 'dist', 'webview', 'graph.js')).toString(),
      styleUri: panel.webview.asWebviewUri(vscode.Uri.joinPath(this.extensionUri, 'media', 'graph.css')).toString(),
      nonce: makeNonce((n) => randomBytes(n)),
    });
    const subscriptions = [
      panel.webview.onDidReceiveMessage((message: unknown) => this.onMessage(message)),
      panel.onDidDispose(() => {
        subscriptions.forEach((d) => d.dispose());
        if (this.panel === panel) {
          this.panel = undefined;
        }
      }),
    ];
  }

  private scheduleRefresh(): void {
    if (this.panel === undefined) {
      return;
    }
    if (this.timer !== undefined) {
      clearTimeout(this.timer);
    }
    this.timer = setTimeout(() => {
      this.timer = undefined;
      void this.refresh();
    }, REFRESH_DELAY_MS);
  }

  /** Asks for the graph and posts it; a refresh asked for while one runs runs once more after it. */
  async refresh(): Promise<void> {
    if (this.running !== undefined) {
      this.again = true;
      return this.running;
    }
    this.running = (async () => {
      do {
        this.again = false;
        await this.post({ type: 'loading' });
        const result = await this.fetchGraph();
        if ('error' in result) {
          await this.post({ type: 'error', message: result.error });
        } else {
          this.latest = result.data;
          this.generated = new Date().toLocaleTimeString();
          await this.post({ type: 'graph', data: result.data, generated: this.generated });
        }
      } while (this.again);
    })().finally(() => {
      this.running = undefined;
    });
    return this.running;
  }

  private async post(message: unknown): Promise<void> {
    if (this.panel !== undefined) {
      await this.panel.webview.postMessage(message);
    }
  }

  private onMessage(message: unknown): void {
    if (typeof message !== 'object' || message === null) {
      return;
    }
    const type = (message as Record<string, unknown>)['type'];
    if (type === 'ready') {
      if (this.latest !== undefined) {
        void this.post({ type: 'graph', data: this.latest, generated: this.generated });
      }
    } else if (type === 'refresh') {
      void this.refresh();
    } else if (isOpenMessage(message)) {
      void this.open(message);
    }
  }

  /** Opens a location of the graph (no other file: the webview's messages are not trusted further). */
  private async open(message: OpenMessage): Promise<void> {
    if (this.latest === undefined || !knownFiles(this.latest).has(message.file)) {
      this.log(`graph panel: refused to open ${message.file}, which the graph does not name`);
      return;
    }
    const column = this.panel?.viewColumn === vscode.ViewColumn.One ? vscode.ViewColumn.Beside : vscode.ViewColumn.One;
    try {
      const document = await vscode.workspace.openTextDocument(vscode.Uri.file(message.file));
      const line = Math.min(Math.max(message.line - 1, 0), Math.max(document.lineCount - 1, 0));
      const character = utf16Column(document.lineAt(line).text, message.column - 1);
      const position = new vscode.Position(line, character);
      await vscode.window.showTextDocument(document, {
        viewColumn: column,
        preview: false,
        selection: new vscode.Range(position, position),
      });
    } catch (error) {
      void vscode.window.showErrorMessage(`iface: cannot open ${message.file}: ${error instanceof Error ? error.message : String(error)}`);
    }
  }

  dispose(): void {
    if (this.timer !== undefined) {
      clearTimeout(this.timer);
    }
    this.panel?.dispose();
    this.disposables.forEach((d) => d.dispose());
  }
}
