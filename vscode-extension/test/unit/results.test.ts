import assert from 'node:assert/strict';
import { describe, it } from 'node:test';

import { asText, parseFiles, previewPath, stringField, stringList, writtenPaths } from '../../src/results';
import { didChangeConfigurationParams, readLaunchSettings, readServerSettings } from '../../src/settings';

describe('server answers', () => {
  it('parses the iface.preview file list', () => {
    assert.deepEqual(parseFiles({ files: [{ path: 'a/b.hpp', text: 'x' }] }), [{ path: 'a/b.hpp', text: 'x' }]);
    assert.deepEqual(parseFiles({ files: [] }), []);
    assert.equal(parseFiles({ files: [{ path: 1 }] }), undefined);
    assert.equal(parseFiles('nope'), undefined);
  });

  it('reads text answers', () => {
    assert.equal(asText('graph TD'), 'graph TD');
    assert.equal(asText({ text: 'digraph {}' }), 'digraph {}');
    assert.equal(asText(null), '');
    assert.equal(asText({ ok: true }), '{\n  "ok": true\n}');
  });

  it('reads written paths of iface.generate', () => {
    assert.deepEqual(writtenPaths({ files: ['a', { path: 'b' }] }), ['a', 'b']);
    assert.deepEqual(writtenPaths({ written: ['c'] }), ['c']);
    assert.deepEqual(writtenPaths('done'), []);
  });

  it('reads the errors, refusals and folder of iface.generate', () => {
    const answer = { folder: '/ws/generated/ros2', errors: ['arm.iface:3: bad', 7], refused: [] };
    assert.deepEqual(stringList(answer, 'errors'), ['arm.iface:3: bad']);
    assert.deepEqual(stringList(answer, 'refused'), []);
    assert.deepEqual(stringList('text', 'errors'), []);
    assert.equal(stringField(answer, 'folder'), '/ws/generated/ros2');
    assert.equal(stringField({ folder: '' }, 'folder'), undefined);
    assert.equal(stringField(null, 'folder'), undefined);
  });

  it('makes virtual document paths without escapes out of the target folder', () => {
    assert.equal(previewPath('ros2', 'msg/JointCommand.msg'), '/ros2/msg/JointCommand.msg');
    assert.equal(previewPath('cpp', '/abs/../x.hpp'), '/cpp/abs/x.hpp');
    assert.equal(previewPath('a b', 'C:\\out\\y.py'), '/a_b/out/y.py');
    assert.equal(previewPath('', ''), '/target/output');
  });
});

describe('settings sent to the server', () => {
  const values: Record<string, unknown> = {
    'output.folder': 'gen',
    targets: ['ros2', 3, 'cpp'],
    includePaths: ['idl'],
    'compat.baseline': 'v1/arm.iface',
    'server.path': '/x/iface-lsp',
  };
  it('mirrors the iface.* settings', () => {
    const settings = readServerSettings((key) => values[key]);
    assert.deepEqual(settings, {
      output: { folder: 'gen' },
      targets: ['ros2', 'cpp'],
      includePaths: ['idl'],
      compat: { baseline: 'v1/arm.iface' },
    });
    assert.deepEqual(didChangeConfigurationParams(settings), { settings: { iface: settings } });
  });

  it('defaults the launch arguments to --stdio', () => {
    assert.deepEqual(readLaunchSettings((key) => values[key]), { path: '/x/iface-lsp', args: ['--stdio'] });
    assert.deepEqual(readServerSettings(() => undefined), {
      output: { folder: '' },
      targets: [],
      includePaths: [],
      compat: { baseline: '' },
    });
  });
});
