// Generate refuses an output folder outside the workspace unless the user confirms.
import assert from 'node:assert/strict';
import { mkdirSync, mkdtempSync, realpathSync, rmSync, symlinkSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, describe, it } from 'node:test';

import { type Answer, type FolderQuestion, containingRoot, folderArgument, isWithin, mayWriteTo, realPath } from '../../src/outputFolder';

const base = realpathSync(mkdtempSync(join(tmpdir(), 'iface-out-')));
const workspace = join(base, 'ws');
const outside = join(base, 'elsewhere');
mkdirSync(join(workspace, 'src'), { recursive: true });
mkdirSync(outside, { recursive: true });
symlinkSync(outside, join(workspace, 'link-out'));
symlinkSync(join(workspace, 'src'), join(base, 'link-in'));
after(() => rmSync(base, { recursive: true, force: true }));

function asker(answer: Answer): { ask: (q: FolderQuestion) => Promise<Answer>; asked: FolderQuestion[] } {
  const asked: FolderQuestion[] = [];
  return {
    asked,
    ask: async (q) => {
      asked.push(q);
      return answer;
    },
  };
}

describe('output folder inside the workspace', () => {
  it('compares paths by their parts, not by their text', () => {
    assert.ok(isWithin('/w/ws', '/w/ws', 'linux'));
    assert.ok(isWithin('/w/ws/generated/ros2', '/w/ws', 'linux'));
    assert.ok(!isWithin('/w/ws-other', '/w/ws', 'linux'));
    assert.ok(!isWithin('/w', '/w/ws', 'linux'));
    assert.ok(isWithin('C:\\Work\\WS\\gen', 'c:\\work\\ws', 'win32') || process.platform !== 'win32');
    assert.ok(!isWithin('/W/WS/gen', '/w/ws', 'linux'));
    assert.ok(isWithin('/W/WS/gen', '/w/ws', 'darwin'));
  });

  it('resolves .. and symbolic links, also of folders that do not exist yet', () => {
    assert.equal(realPath(join(workspace, 'generated', '..', '..', 'elsewhere', 'new')), join(outside, 'new'));
    assert.equal(realPath(join(workspace, 'link-out', 'gen', 'ros2')), join(outside, 'gen', 'ros2'));
    assert.equal(containingRoot(join(workspace, 'generated'), [workspace]), workspace);
    assert.equal(containingRoot(join(workspace, '..', 'elsewhere'), [workspace]), undefined);
    assert.equal(containingRoot(join(workspace, 'link-out', 'gen'), [workspace]), undefined, 'a link that leads out is outside');
    assert.equal(containingRoot(join(base, 'link-in', 'gen'), [workspace]), workspace, 'a link that leads in is inside');
    assert.equal(containingRoot(join(outside, 'gen'), [workspace, outside]), outside);
  });
});

describe('asking before writing outside the workspace', () => {
  const remembered: string[] = [];
  const remember = async (f: string): Promise<void> => {
    remembered.push(f);
  };

  it('does not ask inside the workspace', async () => {
    const { ask, asked } = asker('cancel');
    assert.equal(await mayWriteTo(join(workspace, 'generated'), [workspace], { ask, allowed: [], remember }), true);
    assert.equal(asked.length, 0);
  });

  it('refuses when the user cancels', async () => {
    const { ask, asked } = asker('cancel');
    assert.equal(await mayWriteTo(join(outside, 'gen'), [workspace], { ask, allowed: [], remember }), false);
    assert.deepEqual(asked, [{ folder: join(outside, 'gen'), roots: [workspace] }]);
  });

  it('refuses a link out of the workspace unless confirmed', async () => {
    const { ask, asked } = asker('cancel');
    assert.equal(await mayWriteTo(join(workspace, 'link-out'), [workspace], { ask, allowed: [], remember }), false);
    assert.equal(asked[0]?.folder, outside);
  });

  it('writes once when the user confirms, and asks again next time', async () => {
    const { ask, asked } = asker('once');
    assert.equal(await mayWriteTo(join(outside, 'gen'), [workspace], { ask, allowed: [], remember }), true);
    assert.equal(await mayWriteTo(join(outside, 'gen'), [workspace], { ask, allowed: [], remember }), true);
    assert.equal(asked.length, 2);
    assert.deepEqual(remembered, []);
  });

  it('remembers "always" for that folder and what lies below it', async () => {
    const { ask } = asker('always');
    assert.equal(await mayWriteTo(join(outside, 'gen'), [workspace], { ask, allowed: [], remember }), true);
    assert.deepEqual(remembered, [join(outside, 'gen')]);
    const never = asker('cancel');
    assert.equal(await mayWriteTo(join(outside, 'gen', 'ros2'), [workspace], { ask: never.ask, allowed: remembered, remember }), true);
    assert.equal(await mayWriteTo(join(outside, 'other'), [workspace], { ask: never.ask, allowed: remembered, remember }), false);
    assert.equal(never.asked.length, 1);
  });
});

describe('the folder argument of the server commands', () => {
  it('reads positional and object arguments', () => {
    assert.equal(folderArgument(['file:///a.iface', 'ros2', '/out'], 2), '/out');
    assert.equal(folderArgument(['file:///a.iface', '/out'], 1), '/out');
    assert.equal(folderArgument(['file:///a.iface', 'ros2'], 2), undefined);
    assert.equal(folderArgument([{ uri: 'file:///a.iface', folder: '/f' }], 2), '/f');
    assert.equal(folderArgument([{ uri: 'file:///a.iface', out: '/o' }], 2), '/o');
    assert.equal(folderArgument([{ uri: 'file:///a.iface', folder: '' }], 2), undefined);
  });
});
