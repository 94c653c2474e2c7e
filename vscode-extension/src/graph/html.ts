// The page of the system-graph panel. No `vscode` import here (unit-tested).
//
// Its Content Security Policy allows nothing but the extension's own script
// (by nonce) and style sheet: no network, no inline script or style, no eval.

export interface PageResources {
  /** `webview.cspSource`: the origin of the extension's files inside the webview. */
  cspSource: string;
  scriptUri: string;
  styleUri: string;
  nonce: string;
}

function attr(value: string): string {
  return value.replace(/&/g, '&amp;').replace(/"/g, '&quot;').replace(/</g, '&lt;').replace(/>/g, '&gt;');
}

/** The Content-Security-Policy of the page. */
export function contentSecurityPolicy(r: PageResources): string {
  return [
    "default-src 'none'",
    `style-src ${r.cspSource}`,
    `script-src 'nonce-${r.nonce}'`,
    `img-src ${r.cspSource} data:`,
    `font-src ${r.cspSource}`,
    "base-uri 'none'",
    "form-action 'none'",
  ].join('; ');
}

/** A nonce of 32 characters from `random` (crypto in the extension). */
export function makeNonce(random: (n: number) => Uint8Array): string {
  const alphabet = 'ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789';
  return Array.from(random(32), (byte) => alphabet[byte % alphabet.length]).join('');
}

export function graphPage(r: PageResources): string {
  return `<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="UTF-8">
<meta http-equiv="Content-Security-Policy" content="${attr(contentSecurityPolicy(r))}">
<meta name="viewport" content="width=device-width, initial-scale=1.0">
<link rel="stylesheet" href="${attr(r.styleUri)}">
<title>System graph</title>
</head>
<body class="loading">
<header class="toolbar" role="toolbar" aria-label="System graph">
<button id="refresh" type="button" title="Build the graph again from the workspace">Refresh</button>
<button id="zoom-out" type="button" title="Zoom out" aria-label="Zoom out">−</button>
<button id="zoom-in" type="button" title="Zoom in" aria-label="Zoom in">+</button>
<button id="zoom-fit" type="button" title="Fit to the panel">Fit</button>
<button id="zoom-actual" type="button" title="Actual size">1:1</button>
<span id="status" class="status" role="status">building the graph…</span>
</header>
<main id="graph" class="graph-view" aria-label="System graph: click a component, a link or an open end to go to its definition"></main>
<section class="checks" aria-label="Checks">
<ul id="checks"></ul>
</section>
<script nonce="${attr(r.nonce)}" src="${attr(r.scriptUri)}"></script>
</body>
</html>
`;
}
