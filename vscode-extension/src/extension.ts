// The iface VS Code extension: a thin client of the `iface-lsp` language
// server. Diagnostics, hover, completion and formatting come from the server
// through vscode-languageclient; the commands below gather arguments, call the
// server's workspace/executeCommand and show what it answers.

import * as path from 'node:path';
import * as vscode from 'vscode';
import {
  DidChangeConfigurationNotification,
  ExecuteCommandRequest,
  LanguageClient,
  type LanguageClientOptions,
  RevealOutputChannelOn,
  type ServerOptions,
  State,
} from 'vscode-languageclient/node';

import { parseGraph } from './graph/data';
import { GraphPanel, type GraphResult } from './graph/panel';
import { INSTALL_HINT, expandPath, locateServer } from './locate';
import { type Answer, folderArgument, mayWriteTo } from './outputFolder';
import { asText, parseFiles, previewPath, stringField, stringList, writtenPaths } from './results';
import {
  type IfaceSettings,
  didChangeConfigurationParams,
  readLaunchSettings,
  readServerSettings,
} from './settings';

const LANGUAGE_ID = 'iface';
const PREVIEW_SCHEME = 'iface-preview';
const LAST_TARGET_KEY = 'iface.lastTarget';
/** Output folders outside the workspace that the user allowed for good ("Always for this folder"). */
const ALLOWED_FOLDERS_KEY = 'iface.allowedOutputFolders';
/** Offered after the configured targets; the server says which ones it has when asked for another. */
const SUGGESTED_TARGETS = ['ros2', 'idl', 'px4', 'ardupilot'];

type ServerState = 'starting' | 'running' | 'stopped' | 'not-found' | 'failed';

/** Read-only virtual documents: generated-file previews, compatibility reports, graphs. */
class VirtualDocuments implements vscode.TextDocumentContentProvider {
  private readonly contents = new Map<string, string>();
  private readonly changed = new vscode.EventEmitter<vscode.Uri>();
  readonly onDidChange = this.changed.event;

  provideTextDocumentContent(uri: vscode.Uri): string {
    return this.contents.get(uri.toString()) ?? '';
  }

  set(uri: vscode.Uri, text: string): void {
    this.contents.set(uri.toString(), text);
    this.changed.fire(uri);
  }

  dispose(): void {
    this.changed.dispose();
    this.contents.clear();
  }
}

interface PythonEnvironmentPath {
  path: string;
}

function isRecord(value: unknown): value is Record<string, unknown> {
  return typeof value === 'object' && value !== null;
}

function errorMessage(error: unknown): string {
  if (error instanceof Error) {
    return error.message;
  }
  if (isRecord(error) && typeof error['message'] === 'string') {
    return error['message'];
  }
  return String(error);
}

function withTimeout<T>(promise: Thenable<T>, ms: number): Promise<T | undefined> {
  return new Promise<T | undefined>((resolve) => {
    const timer = setTimeout(() => resolve(undefined), ms);
    promise.then(
      (value) => {
        clearTimeout(timer);
        resolve(value);
      },
      () => {
        clearTimeout(timer);
        resolve(undefined);
      },
    );
  });
}

class IfaceExtension implements vscode.Disposable {
  private client: LanguageClient | undefined;
  private clientDisposables: vscode.Disposable[] = [];
  private readonly output: vscode.OutputChannel;
  private readonly status: vscode.StatusBarItem;
  private readonly documents = new VirtualDocuments();
  private readonly graphPanel: GraphPanel;
  private readonly disposables: vscode.Disposable[] = [];
  private serverCommand = '';
  private serverSource = '';
  private starting: Promise<void> | undefined;
  /** True while this extension itself stops the client (a stop it did not ask for is a failure). */
  private stopping = false;
  private watchingPython = false;

  constructor(private readonly context: vscode.ExtensionContext) {
    this.output = vscode.window.createOutputChannel('iface');
    this.status = vscode.window.createStatusBarItem('iface.status', vscode.StatusBarAlignment.Right, 100);
    this.status.name = 'iface language server';
    this.graphPanel = new GraphPanel(context.extensionUri, () => this.fetchGraph(), (line) => this.output.appendLine(line));
    this.disposables.push(
      this.graphPanel,
      this.output,
      this.status,
      this.documents,
      vscode.workspace.registerTextDocumentContentProvider(PREVIEW_SCHEME, this.documents),
      vscode.commands.registerCommand('iface.generateForTarget', (uri?: unknown) => this.generate(uri)),
      vscode.commands.registerCommand('iface.previewGenerated', (uri?: unknown) => this.preview(uri)),
      vscode.commands.registerCommand('iface.checkCompatibility', (uri?: unknown) => this.compat(uri)),
      vscode.commands.registerCommand('iface.showGraph', () => this.graphPanel.show()),
      vscode.commands.registerCommand('iface.showGraphText', () => this.graphText()),
      vscode.commands.registerCommand('iface.verifyRunning', () => this.verifyRunning()),
      vscode.commands.registerCommand('iface.restartServer', () => this.restart()),
      vscode.commands.registerCommand('iface.showOutput', () => this.output.show(true)),
      vscode.workspace.onDidChangeConfiguration((e) => this.onConfigurationChanged(e)),
    );
    this.setStatus('stopped', 'not started');
    this.status.show();
  }

  // ---- Settings ------------------------------------------------------------

  private config(): vscode.WorkspaceConfiguration {
    return vscode.workspace.getConfiguration('iface');
  }

  private serverSettings(): IfaceSettings {
    const config = this.config();
    return readServerSettings((key) => config.get(key));
  }

  private workspacePaths(): string[] {
    return (vscode.workspace.workspaceFolders ?? []).map((f) => f.uri.fsPath);
  }

  private onConfigurationChanged(event: vscode.ConfigurationChangeEvent): void {
    if (event.affectsConfiguration('iface.server')) {
      this.output.appendLine('iface.server settings changed: restarting the language server.');
      void this.restart();
      return;
    }
    if (event.affectsConfiguration('python.defaultInterpreterPath') && this.client === undefined) {
      void this.restart();
      return;
    }
    if (event.affectsConfiguration('iface') && this.client !== undefined && this.client.isRunning()) {
      void this.client
        .sendNotification(DidChangeConfigurationNotification.type, didChangeConfigurationParams(this.serverSettings()))
        .catch((error: unknown) => this.output.appendLine(`didChangeConfiguration failed: ${errorMessage(error)}`));
    }
  }

  // ---- Server lifecycle ----------------------------------------------------

  private setStatus(state: ServerState, detail: string): void {
    const item = this.status;
    item.backgroundColor = undefined;
    switch (state) {
      case 'starting':
        item.text = '$(sync~spin) iface';
        item.command = 'iface.showOutput';
        break;
      case 'running':
        item.text = '$(check) iface';
        item.command = 'iface.showOutput';
        break;
      case 'stopped':
        item.text = '$(debug-stop) iface';
        item.command = 'iface.restartServer';
        break;
      case 'not-found':
        item.text = '$(warning) iface';
        item.command = 'iface.restartServer';
        item.backgroundColor = new vscode.ThemeColor('statusBarItem.warningBackground');
        break;
      case 'failed':
        item.text = '$(error) iface';
        item.command = 'iface.restartServer';
        item.backgroundColor = new vscode.ThemeColor('statusBarItem.errorBackground');
        break;
    }
    item.tooltip = `iface language server: ${state}${detail === '' ? '' : ` (${detail})`}\n` +
      (item.command === 'iface.restartServer' ? 'Click to restart.' : 'Click to show the server output.');
    item.accessibilityInformation = { label: `iface language server ${state}` };
  }

  /** Restarts the server when the selected Python environment changes and the server came from it (or was not found). */
  private watchPythonEnvironment(environments: unknown): void {
    if (this.watchingPython || !isRecord(environments) || typeof environments['onDidChangeActiveEnvironmentPath'] !== 'function') {
      return;
    }
    this.watchingPython = true;
    const onDidChange = environments['onDidChangeActiveEnvironmentPath'] as vscode.Event<unknown>;
    this.disposables.push(
      onDidChange.call(environments, () => {
        if (this.client === undefined || this.serverSource === 'python') {
          this.output.appendLine('The selected Python environment changed: restarting the language server.');
          void this.restart();
        }
      }),
    );
  }

  private async pythonEnvironments(): Promise<string[]> {
    const found: string[] = [];
    const resource = vscode.window.activeTextEditor?.document.uri ?? vscode.workspace.workspaceFolders?.[0]?.uri;
    const extension = vscode.extensions.getExtension<unknown>('ms-python.python');
    if (extension !== undefined) {
      const api: unknown = extension.isActive ? extension.exports : await withTimeout(extension.activate(), 15000);
      if (isRecord(api)) {
        const environments = api['environments'];
        this.watchPythonEnvironment(environments);
        if (isRecord(environments) && typeof environments['getActiveEnvironmentPath'] === 'function') {
          try {
            const getPath = environments['getActiveEnvironmentPath'] as (r?: vscode.Uri) => unknown;
            const active = getPath.call(environments, resource);
            if (isRecord(active) && typeof active['path'] === 'string') {
              found.push((active as unknown as PythonEnvironmentPath).path);
            }
          } catch (error) {
            this.output.appendLine(`Python extension: ${errorMessage(error)}`);
          }
        }
        const settings = api['settings'];
        if (isRecord(settings) && typeof settings['getExecutionDetails'] === 'function') {
          try {
            const details: unknown = (settings['getExecutionDetails'] as (r?: vscode.Uri) => unknown).call(settings, resource);
            if (isRecord(details) && Array.isArray(details['execCommand'])) {
              const first: unknown = details['execCommand'][0];
              if (typeof first === 'string') {
                found.push(first);
              }
            }
          } catch (error) {
            this.output.appendLine(`Python extension: ${errorMessage(error)}`);
          }
        }
      }
    }
    const configured = vscode.workspace.getConfiguration('python', resource).get<string>('defaultInterpreterPath');
    if (configured !== undefined && configured !== '' && configured !== 'python' && configured !== 'python3') {
      found.push(expandPath(configured, this.workspacePaths(), process.env));
    }
    return found.filter((p) => path.isAbsolute(p));
  }

  async start(): Promise<void> {
    if (this.starting !== undefined) {
      return this.starting;
    }
    this.starting = this.doStart().finally(() => {
      this.starting = undefined;
    });
    return this.starting;
  }

  private async doStart(): Promise<void> {
    this.setStatus('starting', 'looking for iface-lsp');
    const config = this.config();
    const launch = readLaunchSettings((key) => config.get(key));
    const located = await locateServer({
      configuredPath: launch.path,
      pythonEnvironments: await this.pythonEnvironments(),
      workspaceFolders: this.workspacePaths(),
      env: process.env,
      platform: process.platform,
    });
    if (!located.found) {
      this.setStatus('not-found', located.reason);
      this.output.appendLine(`${located.reason} Searched:\n  ${located.searched.join('\n  ')}`);
      this.output.appendLine(INSTALL_HINT);
      void this.showNotFound(located.reason);
      return;
    }
    this.serverCommand = located.command;
    this.serverSource = located.source;
    this.output.appendLine(`Starting ${located.command} ${launch.args.join(' ')} (found via ${located.source})`);

    const serverOptions: ServerOptions = {
      run: { command: located.command, args: launch.args, options: { env: process.env } },
      debug: { command: located.command, args: launch.args, options: { env: process.env } },
    };
    const watcher = vscode.workspace.createFileSystemWatcher('**/*.iface');
    const clientOptions: LanguageClientOptions = {
      documentSelector: [
        { scheme: 'file', language: LANGUAGE_ID },
        { scheme: 'untitled', language: LANGUAGE_ID },
      ],
      initializationOptions: this.serverSettings(),
      outputChannel: this.output,
      revealOutputChannelOn: RevealOutputChannelOn.Never,
      synchronize: { fileEvents: watcher },
      middleware: {
        // Code lenses and code actions run the server's write commands directly: the same
        // check of the output folder as the Generate command applies to them.
        executeCommand: async (command, args, next) => {
          if ((command === 'iface.generate' || command === 'iface.exportJson') && !(await this.confirmWriteCommand(command, args))) {
            return undefined;
          }
          return next(command, args);
        },
      },
    };
    const client = new LanguageClient(LANGUAGE_ID, 'iface', serverOptions, clientOptions);
    this.client = client;
    this.clientDisposables = [
      watcher,
      client.onDidChangeState((event) => {
        if (this.client !== client) {
          return;
        }
        if (event.newState === State.Running) {
          this.setStatus('running', `${this.serverCommand} via ${this.serverSource}`);
        } else if (event.newState === State.Starting) {
          this.setStatus('starting', this.serverCommand);
        } else if (this.stopping) {
          this.setStatus('stopped', this.serverCommand);
        } else {
          this.setStatus('failed', `${this.serverCommand} stopped; see the iface output`);
        }
      }),
    ];
    try {
      await client.start();
      this.setStatus('running', `${this.serverCommand} via ${this.serverSource}`);
    } catch (error) {
      const message = errorMessage(error);
      this.setStatus('failed', message);
      this.output.appendLine(`The language server failed to start: ${message}`);
      void vscode.window
        .showErrorMessage(`iface: the language server (${located.command}) failed to start: ${message}`, 'Show Output', 'Restart')
        .then((choice) => this.onChoice(choice));
    }
  }

  private async showNotFound(reason: string): Promise<void> {
    const choice = await vscode.window.showWarningMessage(
      `iface: ${reason} ${INSTALL_HINT}`,
      'Open Settings',
      'Retry',
    );
    await this.onChoice(choice);
  }

  private async onChoice(choice: string | undefined): Promise<void> {
    if (choice === 'Open Settings') {
      await vscode.commands.executeCommand('workbench.action.openSettings', 'iface.server');
    } else if (choice === 'Retry' || choice === 'Restart') {
      await this.restart();
    } else if (choice === 'Show Output') {
      this.output.show(true);
    }
  }

  async stop(): Promise<void> {
    const client = this.client;
    this.client = undefined;
    for (const d of this.clientDisposables) {
      d.dispose();
    }
    this.clientDisposables = [];
    if (client !== undefined) {
      this.stopping = true;
      try {
        await client.dispose(3000);
      } catch (error) {
        this.output.appendLine(`Stopping the language server: ${errorMessage(error)}`);
      } finally {
        this.stopping = false;
      }
    }
    this.setStatus('stopped', 'stopped');
  }

  async restart(): Promise<void> {
    if (this.starting !== undefined) {
      await this.starting;
    }
    await this.stop();
    await this.start();
  }

  // ---- Commands --------------------------------------------------------------

  private documentUri(arg: unknown): vscode.Uri | undefined {
    if (arg instanceof vscode.Uri) {
      return arg;
    }
    const editor = vscode.window.activeTextEditor;
    if (editor !== undefined && editor.document.languageId === LANGUAGE_ID) {
      return editor.document.uri;
    }
    void vscode.window.showErrorMessage('iface: open an .iface file first.');
    return undefined;
  }

  private runningClient(): LanguageClient | undefined {
    if (this.client !== undefined && this.client.isRunning()) {
      return this.client;
    }
    void vscode.window
      .showErrorMessage('iface: the language server is not running.', 'Restart', 'Show Output')
      .then((choice) => this.onChoice(choice));
    return undefined;
  }

  /** Calls the server's workspace/executeCommand; undefined (after a message) on failure. */
  private async execute(command: string, args: Record<string, unknown>, title: string): Promise<{ ok: true; result: unknown } | undefined> {
    const client = this.runningClient();
    if (client === undefined) {
      return undefined;
    }
    try {
      const result: unknown = await vscode.window.withProgress(
        { location: vscode.ProgressLocation.Window, title },
        () => client.sendRequest(ExecuteCommandRequest.type, { command, arguments: [args] }),
      );
      return { ok: true, result };
    } catch (error) {
      void vscode.window.showErrorMessage(`iface: ${command} failed: ${errorMessage(error)}`);
      return undefined;
    }
  }

  private async pickTarget(title: string): Promise<string | undefined> {
    const configured = this.serverSettings().targets;
    const last = this.context.workspaceState.get<string>(LAST_TARGET_KEY);
    const names = [...new Set([...(last !== undefined && last !== '' ? [last] : []), ...configured, ...SUGGESTED_TARGETS])];
    const base: vscode.QuickPickItem[] = names.map((name) => ({
      label: name,
      description: configured.includes(name) ? 'iface.targets' : name === last ? 'last used' : 'suggested',
    }));
    const pick = vscode.window.createQuickPick<vscode.QuickPickItem>();
    pick.title = title;
    pick.placeholder = 'Pick a target, or type another target name (iface.targets lists yours first)';
    pick.items = base;
    pick.onDidChangeValue((value) => {
      const typed = value.trim();
      pick.items = typed !== '' && !names.includes(typed) ? [{ label: typed, description: 'target' }, ...base] : base;
    });
    const target = await new Promise<string | undefined>((resolve) => {
      pick.onDidAccept(() => {
        const chosen = pick.selectedItems[0]?.label ?? pick.value.trim();
        resolve(chosen === '' ? undefined : chosen);
        pick.hide();
      });
      pick.onDidHide(() => {
        resolve(undefined);
        pick.dispose();
      });
      pick.show();
    });
    if (target !== undefined) {
      await this.context.workspaceState.update(LAST_TARGET_KEY, target);
    }
    return target;
  }

  private outputFolder(uri: vscode.Uri): string | undefined {
    const folder = this.serverSettings().output.folder.trim();
    return folder === '' ? undefined : this.resolveFolder(folder, uri);
  }

  /** A folder setting or argument as an absolute path (relative to the workspace folder of `uri`). */
  private resolveFolder(folder: string, uri: vscode.Uri): string {
    const workspaceFolder = vscode.workspace.getWorkspaceFolder(uri);
    const expanded = expandPath(folder, workspaceFolder !== undefined ? [workspaceFolder.uri.fsPath] : this.workspacePaths(), process.env);
    if (path.isAbsolute(expanded)) {
      return expanded;
    }
    const base = workspaceFolder?.uri.fsPath ?? path.dirname(uri.fsPath);
    return path.resolve(base, expanded);
  }

  /** The folders that count as the workspace for `uri`: the workspace folders, else the document's folder. */
  private workspaceRoots(uri: vscode.Uri): string[] {
    const roots = this.workspacePaths();
    return roots.length > 0 ? roots : [path.dirname(uri.fsPath)];
  }

  /**
   * True when files may be written into `folder`: it is inside the workspace, the user allowed it
   * for good before, or the user confirms now (a modal question; Cancel refuses).
   */
  async confirmOutputFolder(folder: string, uri: vscode.Uri): Promise<boolean> {
    const allowed = this.context.workspaceState.get<string[]>(ALLOWED_FOLDERS_KEY) ?? [];
    const ok = await mayWriteTo(folder, this.workspaceRoots(uri), {
      allowed,
      remember: async (f) => this.context.workspaceState.update(ALLOWED_FOLDERS_KEY, [...allowed, f]),
      ask: async ({ folder: target, roots }) => {
        const once = 'Generate';
        const always = 'Always for This Folder';
        const choice = await vscode.window.showWarningMessage(
          'iface: the output folder is outside the workspace. Write generated files there?',
          {
            modal: true,
            detail: `${target}\n\nis not inside ${roots.join(', ')}. Files that iface generated there before are overwritten. ` +
              'Set iface.output.folder to a folder of the workspace to write there without asking.',
          },
          once,
          always,
        );
        const answer: Answer = choice === once ? 'once' : choice === always ? 'always' : 'cancel';
        return answer;
      },
    });
    if (!ok) {
      this.output.appendLine(`Not generating into ${folder}: it is outside the workspace and was not confirmed.`);
    }
    return ok;
  }

  /** The output-folder check for iface.generate / iface.exportJson run by a code lens or code action. */
  private async confirmWriteCommand(command: string, args: unknown[]): Promise<boolean> {
    const first = args[0];
    const uriText = typeof first === 'string' ? first : typeof first === 'object' && first !== null ? (first as Record<string, unknown>)['uri'] : undefined;
    if (typeof uriText !== 'string') {
      return true; // the server answers a missing uri with an error
    }
    const uri = vscode.Uri.parse(uriText);
    const given = folderArgument(args, command === 'iface.generate' ? 2 : 1);
    const folder = given !== undefined ? this.resolveFolder(given, uri) : this.outputFolder(uri);
    return folder === undefined || this.confirmOutputFolder(folder, uri);
  }

  private async generate(arg: unknown): Promise<void> {
    const uri = this.documentUri(arg);
    if (uri === undefined || this.runningClient() === undefined) {
      return;
    }
    const target = await this.pickTarget('iface: Generate for target');
    if (target === undefined) {
      return;
    }
    const out = this.outputFolder(uri);
    if (out !== undefined && !(await this.confirmOutputFolder(out, uri))) {
      return;
    }
    const args: Record<string, unknown> = { uri: uri.toString(), target };
    if (out !== undefined) {
      // `out` as documented; `folder` is the same for servers that call it so.
      args['out'] = out;
      args['folder'] = out;
    }
    const answer = await this.execute('iface.generate', args, `iface: generating ${target}`);
    if (answer === undefined) {
      return;
    }
    const folder = stringField(answer.result, 'folder') ?? out;
    const where = folder !== undefined ? ` into ${folder}` : '';
    const errors = stringList(answer.result, 'errors');
    if (errors.length > 0) {
      this.output.appendLine(`iface.generate ${target}: ${errors.length} error(s)`);
      errors.forEach((e) => this.output.appendLine(`  ${e}`));
      const more = errors.length > 1 ? ` (and ${errors.length - 1} more)` : '';
      void vscode.window
        .showErrorMessage(`iface: generating ${target} failed: ${errors[0] ?? ''}${more}`, 'Show Output')
        .then((choice) => this.onChoice(choice));
      return;
    }
    const refused = stringList(answer.result, 'refused');
    if (refused.length > 0) {
      this.output.appendLine(`iface.generate ${target}: not overwritten:`);
      refused.forEach((r) => this.output.appendLine(`  ${r}`));
      void vscode.window
        .showWarningMessage(`iface: ${refused.length} file(s) were not overwritten${where}: ${refused.slice(0, 3).join(', ')}`, 'Show Output')
        .then((choice) => this.onChoice(choice));
    }
    const written = writtenPaths(answer.result);
    if (written.length === 0) {
      const text = typeof answer.result === 'string' ? answer.result.trim() : '';
      void vscode.window.showInformationMessage(`iface: generated ${target}${where}.${text !== '' && text.length < 300 ? ` ${text}` : ''}`);
      return;
    }
    const choice = await vscode.window.showInformationMessage(
      `iface: generated ${written.length} file${written.length === 1 ? '' : 's'} for ${target}${where}.`,
      'Open',
    );
    const first = written[0];
    if (choice === 'Open' && first !== undefined) {
      const file = path.isAbsolute(first) ? vscode.Uri.file(first) : vscode.Uri.file(path.resolve(folder ?? path.dirname(uri.fsPath), first));
      await vscode.window.showTextDocument(file, { preview: false });
    }
  }

  private async preview(arg: unknown): Promise<void> {
    const uri = this.documentUri(arg);
    if (uri === undefined || this.runningClient() === undefined) {
      return;
    }
    const target = await this.pickTarget('iface: Preview generated files');
    if (target === undefined) {
      return;
    }
    const answer = await this.execute('iface.preview', { uri: uri.toString(), target }, `iface: previewing ${target}`);
    if (answer === undefined) {
      return;
    }
    const files = parseFiles(answer.result);
    if (files === undefined) {
      void vscode.window.showErrorMessage('iface: the server answered iface.preview with no file list.');
      return;
    }
    const errors = stringList(answer.result, 'errors');
    if (errors.length > 0) {
      errors.forEach((e) => this.output.appendLine(`iface.preview ${target}: ${e}`));
      void vscode.window
        .showWarningMessage(`iface: ${target}: ${errors[0] ?? ''}${errors.length > 1 ? ` (and ${errors.length - 1} more)` : ''}`, 'Show Output')
        .then((choice) => this.onChoice(choice));
    }
    if (files.length === 0) {
      if (errors.length === 0) {
        void vscode.window.showInformationMessage(`iface: target ${target} generates no files for ${path.basename(uri.fsPath)}.`);
      }
      return;
    }
    const uris = files.map((file) => {
      const virtual = vscode.Uri.from({ scheme: PREVIEW_SCHEME, path: previewPath(target, file.path) });
      this.documents.set(virtual, file.text);
      return { file, virtual };
    });
    let chosen = uris;
    if (uris.length > 1) {
      const all: vscode.QuickPickItem = { label: `$(files) Open all ${uris.length} files` };
      const items: vscode.QuickPickItem[] = [all, ...uris.map((u) => ({ label: u.file.path }))];
      const picked = await vscode.window.showQuickPick(items, { title: `iface: ${target} files`, placeHolder: 'File to preview' });
      if (picked === undefined) {
        return;
      }
      chosen = picked === all ? uris : uris.filter((u) => u.file.path === picked.label);
    }
    for (const [index, item] of chosen.entries()) {
      await vscode.window.showTextDocument(item.virtual, { preview: false, preserveFocus: index < chosen.length - 1 });
    }
  }

  /**
   * A baseline as `old` (a file URI for files, else the text as is, e.g. `git:HEAD~1`)
   * and as `baseline` (an absolute path for files, else the text as is).
   */
  private baselineArguments(value: string, uri: vscode.Uri): { old: string; baseline: string } {
    if (/^file:\/\//.test(value)) {
      return { old: value, baseline: vscode.Uri.parse(value).fsPath };
    }
    // Other schemes and revisions (`git:REV`) but not Windows drive letters (`C:\`).
    if (/^[A-Za-z][A-Za-z0-9+.-]+:/.test(value)) {
      return { old: value, baseline: value };
    }
    const workspaceFolder = vscode.workspace.getWorkspaceFolder(uri);
    const folders = workspaceFolder !== undefined ? [workspaceFolder.uri.fsPath] : this.workspacePaths();
    const expanded = expandPath(value, folders, process.env);
    const looksLikePath = path.isAbsolute(expanded) || value.endsWith('.iface') || value.includes('/') || value.includes('\\');
    if (!looksLikePath) {
      return { old: value, baseline: value };
    }
    const absolute = path.isAbsolute(expanded) ? expanded : path.resolve(folders[0] ?? path.dirname(uri.fsPath), expanded);
    return { old: vscode.Uri.file(absolute).toString(), baseline: absolute };
  }

  private async compat(arg: unknown): Promise<void> {
    const uri = this.documentUri(arg);
    if (uri === undefined || this.runningClient() === undefined) {
      return;
    }
    const baseline = this.serverSettings().compat.baseline.trim();
    const items: (vscode.QuickPickItem & { id: string })[] = [];
    if (baseline !== '') {
      items.push({ id: 'setting', label: baseline, description: 'iface.compat.baseline' });
    }
    items.push(
      { id: 'file', label: '$(file) Choose an .iface file…' },
      { id: 'input', label: '$(edit) Enter a path or git:REV…' },
    );
    const picked = await vscode.window.showQuickPick(items, {
      title: 'iface: Check compatibility against…',
      placeHolder: 'The old interface to compare this file with',
    });
    if (picked === undefined) {
      return;
    }
    let old: { old: string; baseline: string } | undefined;
    if (picked.id === 'setting') {
      old = this.baselineArguments(baseline, uri);
    } else if (picked.id === 'file') {
      const options: vscode.OpenDialogOptions = {
        canSelectMany: false,
        filters: { iface: ['iface'] },
        openLabel: 'Compare against',
      };
      const folder = vscode.workspace.getWorkspaceFolder(uri);
      if (folder !== undefined) {
        options.defaultUri = folder.uri;
      }
      const files = await vscode.window.showOpenDialog(options);
      const file = files?.[0];
      old = file !== undefined ? { old: file.toString(), baseline: file.fsPath } : undefined;
    } else {
      const typed = await vscode.window.showInputBox({
        title: 'iface: Check compatibility against…',
        prompt: 'Path of the old .iface file, or git:REV for this file at a git revision',
        value: baseline,
      });
      old = typed !== undefined && typed.trim() !== '' ? this.baselineArguments(typed.trim(), uri) : undefined;
    }
    if (old === undefined) {
      return;
    }
    // `old`/`new` as documented; `uri`/`baseline` are the same for servers that call them so.
    const answer = await this.execute(
      'iface.compat',
      { old: old.old, new: uri.toString(), uri: uri.toString(), baseline: old.baseline },
      'iface: checking compatibility',
    );
    if (answer === undefined) {
      return;
    }
    const name = path.basename(uri.fsPath).replace(/\.iface$/, '');
    const virtual = vscode.Uri.from({ scheme: PREVIEW_SCHEME, path: `/compat/${name}.compat.txt` });
    this.documents.set(virtual, asText(answer.result));
    await vscode.window.showTextDocument(virtual, { preview: false });
  }

  /** The .iface files of the workspace and the active one, as URIs (the server reads its own index; older servers read these). */
  /** Verify against the running system: the server compares the ROS 2 graph with the workspace's files and
   * publishes the findings as diagnostics on them; the report opens beside. */
  private async verifyRunning(): Promise<void> {
    const uris = await this.graphUris();
    if (uris.length === 0) {
      void vscode.window.showErrorMessage('iface: no .iface files in this workspace.');
      return;
    }
    const answer = await this.execute('iface.verify', { uris }, 'iface: verifying against the running system');
    if (answer === undefined) {
      return;
    }
    const virtual = vscode.Uri.from({ scheme: PREVIEW_SCHEME, path: '/verify/running-system.txt' });
    this.documents.set(virtual, asText(answer.result));
    await vscode.window.showTextDocument(virtual, { preview: false });
  }

  private async graphUris(): Promise<string[]> {
    const found = await vscode.workspace.findFiles('**/*.iface', '**/{node_modules,.git}/**');
    const active = vscode.window.activeTextEditor?.document;
    const uris = found.map((u) => u.toString());
    if (active !== undefined && active.languageId === LANGUAGE_ID && !uris.includes(active.uri.toString())) {
      uris.push(active.uri.toString());
    }
    return uris.sort();
  }

  /** The graph for the panel: the server's `iface.graph` answer in `json`, or why there is none. */
  private async fetchGraph(): Promise<GraphResult> {
    if (this.starting !== undefined) {
      await this.starting;
    }
    const running = this.client;
    if (running === undefined || !running.isRunning()) {
      return { error: 'The iface language server is not running (see the iface output, or run "iface: Restart server").' };
    }
    try {
      const result: unknown = await running.sendRequest(ExecuteCommandRequest.type, {
        command: 'iface.graph',
        arguments: [{ uris: await this.graphUris(), format: 'json' }],
      });
      const data = parseGraph(result);
      return data !== undefined ? { data } : { error: 'The server answered iface.graph without a graph (an older iface-lsp?).' };
    } catch (error) {
      return { error: `iface.graph failed: ${errorMessage(error)}` };
    }
  }

  private async graphText(): Promise<void> {
    if (this.runningClient() === undefined) {
      return;
    }
    const format = await vscode.window.showQuickPick(
      [
        { label: 'mermaid', description: 'Mermaid flowchart' },
        { label: 'dot', description: 'Graphviz DOT' },
        { label: 'json', description: 'the graph as data, with locations and checks' },
      ],
      { title: 'iface: Show system graph as text', placeHolder: 'Graph format' },
    );
    if (format === undefined) {
      return;
    }
    const uris = await this.graphUris();
    if (uris.length === 0) {
      void vscode.window.showErrorMessage('iface: no .iface files in this workspace.');
      return;
    }
    const answer = await this.execute('iface.graph', { uris, format: format.label }, 'iface: building the system graph');
    if (answer === undefined) {
      return;
    }
    const extension = format.label === 'dot' ? 'dot' : format.label === 'json' ? 'json' : 'mmd';
    const virtual = vscode.Uri.from({ scheme: PREVIEW_SCHEME, path: `/graph/system.${extension}` });
    this.documents.set(virtual, asText(answer.result));
    await vscode.window.showTextDocument(virtual, { preview: false });
  }

  dispose(): void {
    for (const d of this.disposables) {
      d.dispose();
    }
  }
}

let extension: IfaceExtension | undefined;

export function activate(context: vscode.ExtensionContext): void {
  extension = new IfaceExtension(context);
  context.subscriptions.push(extension);
  // Not awaited: activation stays quick while the server starts.
  void extension.start();
}

export async function deactivate(): Promise<void> {
  if (extension !== undefined) {
    await extension.stop();
    extension = undefined;
  }
}
