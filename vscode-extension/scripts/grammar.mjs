// Source of syntaxes/iface.tmLanguage.json.
//
// The TextMate grammar is written here with String.raw regular expressions
// (no JSON double escaping) and written out by `node scripts/grammar.mjs`.
// `npm test` fails when the committed JSON differs from what this file makes
// (`node scripts/grammar.mjs --check`, run by test/unit/manifest.test.ts), so
// edit this file, then regenerate.
//
// The grammar follows ../grammar.lark: headers, wiring, definitions with
// bodies, fields, types, constant values, annotations and comments.
// TextMate works line by line with regular expressions, so names are scoped
// by position: a definition's name follows its keyword; inside a body, an
// identifier followed by `=`, `,`, `;`, `}`, `)`, `(`, a comment or the end of
// the line is a field name, any other one is a type.

import { readFileSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const ID = String.raw`[A-Za-z_][A-Za-z0-9_]*`;
const QID = String.raw`${ID}(?:\.${ID})*`;
/** Start of a word: not after a word character or a dot (dotted names). */
const B = String.raw`(?<![\w.])`;
/** End of a word: not before a word character or a dot. */
const E = String.raw`(?![\w.])`;
/** What may follow a field or constant name. */
const AFTER_NAME = String.raw`(?=\s*(?:[=,;})(]|$|//|#|/\*))`;

export const BUILTIN_TYPES = [
  'bool', 'byte', 'i8', 'i16', 'i32', 'i64', 'double', 'binary', 'uuid',
  'u8', 'u16', 'u32', 'u64', 'int8', 'int16', 'int32', 'int64',
  'uint8', 'uint16', 'uint32', 'uint64', 'float', 'float32', 'float64',
  'char', 'wchar', 'octet', 'string', 'wstring',
];
export const STRUCT_KINDS = ['struct', 'union', 'exception', 'message', 'configuration', 'state'];
export const SECTION_NAMES = ['request', 'response', 'goal', 'result', 'feedback'];
export const DIRECTIONS = ['publishes', 'subscribes', 'provides', 'calls'];

const alt = (words) => words.join('|');

const block = (contentName, patterns) => ({
  begin: String.raw`\{`,
  beginCaptures: { 0: { name: 'punctuation.section.block.begin.iface' } },
  end: String.raw`\}`,
  endCaptures: { 0: { name: 'punctuation.section.block.end.iface' } },
  name: `meta.block.${contentName}.iface`,
  patterns,
});

const grammar = {
  $schema: 'https://raw.githubusercontent.com/martinring/tmlanguage/master/tmlanguage.json',
  name: 'iface',
  scopeName: 'source.iface',
  fileTypes: ['iface'],
  patterns: [
    { include: '#comments' },
    { include: '#include' },
    { include: '#namespace' },
    { include: '#component' },
    { include: '#instance' },
    { include: '#external' },
    { include: '#wiring' },
    { include: '#const' },
    { include: '#typedef' },
    { include: '#enum' },
    { include: '#senum' },
    { include: '#struct' },
    { include: '#service' },
    { include: '#annotations' },
    { include: '#strings' },
    { include: '#numbers' },
    { include: '#separators' },
  ],
  repository: {
    // ---- Comments --------------------------------------------------------
    comments: {
      patterns: [
        {
          name: 'comment.block.documentation.iface',
          begin: String.raw`/\*\*(?!/)`,
          beginCaptures: { 0: { name: 'punctuation.definition.comment.begin.iface' } },
          end: String.raw`\*/`,
          endCaptures: { 0: { name: 'punctuation.definition.comment.end.iface' } },
        },
        {
          name: 'comment.block.iface',
          begin: String.raw`/\*`,
          beginCaptures: { 0: { name: 'punctuation.definition.comment.begin.iface' } },
          end: String.raw`\*/`,
          endCaptures: { 0: { name: 'punctuation.definition.comment.end.iface' } },
        },
        {
          name: 'comment.line.double-slash.iface',
          match: String.raw`(//).*$`,
          captures: { 1: { name: 'punctuation.definition.comment.iface' } },
        },
        {
          name: 'comment.line.number-sign.iface',
          match: String.raw`(#).*$`,
          captures: { 1: { name: 'punctuation.definition.comment.iface' } },
        },
      ],
    },

    // ---- Literals --------------------------------------------------------
    strings: {
      patterns: [
        {
          name: 'string.quoted.double.iface',
          begin: '"',
          beginCaptures: { 0: { name: 'punctuation.definition.string.begin.iface' } },
          end: String.raw`(")|$`,
          endCaptures: { 1: { name: 'punctuation.definition.string.end.iface' } },
          patterns: [{ include: '#escape' }],
        },
        {
          name: 'string.quoted.single.iface',
          begin: "'",
          beginCaptures: { 0: { name: 'punctuation.definition.string.begin.iface' } },
          end: String.raw`(')|$`,
          endCaptures: { 1: { name: 'punctuation.definition.string.end.iface' } },
          patterns: [{ include: '#escape' }],
        },
      ],
    },
    escape: {
      name: 'constant.character.escape.iface',
      match: String.raw`\\.`,
    },
    numbers: {
      patterns: [
        {
          name: 'constant.numeric.float.iface',
          match: String.raw`${B}[+-]?(?:[0-9]+\.[0-9]*(?:[eE][+-]?[0-9]+)?|\.[0-9]+(?:[eE][+-]?[0-9]+)?|[0-9]+[eE][+-]?[0-9]+)${E}`,
        },
        {
          name: 'constant.numeric.integer.hexadecimal.iface',
          match: String.raw`${B}[+-]?0[xX][0-9A-Fa-f]+${E}`,
        },
        {
          name: 'constant.numeric.integer.decimal.iface',
          match: String.raw`${B}[+-]?[0-9]+${E}`,
        },
      ],
    },
    separators: {
      name: 'punctuation.separator.iface',
      match: '[,;]',
    },

    // ---- Headers ---------------------------------------------------------
    include: {
      match: String.raw`${B}(include|cpp_include)${E}`,
      captures: { 1: { name: 'keyword.control.import.iface' } },
    },
    namespace: {
      match: String.raw`${B}(namespace)${E}(?:\s+(\*|${ID})${E}(?:\s+(${QID})${E})?)?`,
      captures: {
        1: { name: 'keyword.other.namespace.iface' },
        2: { name: 'support.constant.namespace-scope.iface' },
        3: { name: 'entity.name.namespace.iface' },
      },
    },
    component: {
      match: String.raw`${B}(component|system)${E}(?:\s+(${ID})${E})?(?:\s+(version)${E})?|${B}(version)${E}`,
      captures: {
        1: { name: 'storage.type.component.iface' },
        2: { name: 'entity.name.type.component.iface' },
        3: { name: 'keyword.other.version.iface' },
        4: { name: 'keyword.other.version.iface' },
      },
    },
    instance: {
      match: String.raw`${B}(instance)${E}(?:\s+(${ID})${E})?(?:\s*(:)\s*(${ID})${E})?`,
      captures: {
        1: { name: 'storage.type.instance.iface' },
        2: { name: 'entity.name.instance.iface' },
        3: { name: 'punctuation.separator.type.iface' },
        4: { name: 'entity.name.type.component.iface' },
      },
    },
    external: {
      match: String.raw`${B}(external)${E}(?:\s+(${QID})${E})?`,
      captures: {
        1: { name: 'keyword.other.external.iface' },
        2: { name: 'entity.name.namespace.iface' },
      },
    },

    // ---- Wiring ----------------------------------------------------------
    wiring: {
      match: String.raw`${B}(${alt(DIRECTIONS)})${E}(?:\s+(${QID})${E})?(?:\s+(on)${E})?|${B}(on)${E}`,
      captures: {
        1: { name: 'keyword.other.wiring.iface' },
        2: { name: 'entity.name.type.iface' },
        3: { name: 'keyword.other.on.iface' },
        4: { name: 'keyword.other.on.iface' },
      },
    },

    // ---- Definitions -----------------------------------------------------
    const: {
      name: 'meta.const.iface',
      begin: String.raw`${B}(const)${E}`,
      beginCaptures: { 1: { name: 'storage.type.const.iface' } },
      end: String.raw`(?=[,;}]|$)`,
      patterns: [
        { include: '#comments' },
        {
          name: 'variable.other.constant.iface',
          match: String.raw`${B}${ID}(?=\s*=)`,
        },
        { include: '#default-value' },
        { include: '#types' },
      ],
    },
    typedef: {
      name: 'meta.typedef.iface',
      begin: String.raw`${B}(typedef)${E}`,
      beginCaptures: { 1: { name: 'storage.type.typedef.iface' } },
      end: String.raw`${B}(${ID})(?=\s*(?:$|[,;(]|//|#|/\*))`,
      endCaptures: { 1: { name: 'entity.name.type.typedef.iface' } },
      patterns: [{ include: '#comments' }, { include: '#types' }],
    },
    enum: {
      name: 'meta.enum.iface',
      begin: String.raw`${B}(enum)${E}(?:\s+(${ID})${E})?`,
      beginCaptures: {
        1: { name: 'storage.type.enum.iface' },
        2: { name: 'entity.name.type.enum.iface' },
      },
      end: String.raw`(?<=\})`,
      patterns: [
        { include: '#comments' },
        block('enum', [
          { include: '#comments' },
          { include: '#annotations' },
          { include: '#default-value' },
          { name: 'variable.other.enummember.iface', match: String.raw`${B}${ID}${E}` },
          { include: '#separators' },
        ]),
      ],
    },
    senum: {
      name: 'meta.senum.iface',
      begin: String.raw`${B}(senum)${E}(?:\s+(${ID})${E})?`,
      beginCaptures: {
        1: { name: 'storage.type.senum.iface' },
        2: { name: 'entity.name.type.senum.iface' },
      },
      end: String.raw`(?<=\})`,
      patterns: [
        { include: '#comments' },
        block('senum', [
          { include: '#comments' },
          { include: '#strings' },
          { include: '#separators' },
        ]),
      ],
    },
    struct: {
      name: 'meta.$1.iface',
      begin: String.raw`${B}(${alt(STRUCT_KINDS)})${E}(?:\s+(${ID})${E})?`,
      beginCaptures: {
        1: { name: 'storage.type.$1.iface' },
        2: { name: 'entity.name.type.$1.iface' },
      },
      end: String.raw`(?<=\})`,
      patterns: [
        { include: '#comments' },
        { name: 'keyword.other.xsd-all.iface', match: String.raw`${B}xsd_all${E}` },
        block('struct', [{ include: '#members' }]),
      ],
    },
    service: {
      name: 'meta.$1.iface',
      begin: String.raw`${B}(service|action)${E}(?:\s+(${ID})${E})?`,
      beginCaptures: {
        1: { name: 'storage.type.$1.iface' },
        2: { name: 'entity.name.type.$1.iface' },
      },
      end: String.raw`(?<=\})`,
      patterns: [
        { include: '#comments' },
        {
          match: String.raw`${B}(extends)${E}(?:\s+(${QID})${E})?`,
          captures: {
            1: { name: 'storage.modifier.extends.iface' },
            2: { name: 'entity.other.inherited-class.iface' },
          },
        },
        block('service', [{ include: '#service-members' }]),
      ],
    },

    // ---- Bodies ----------------------------------------------------------
    'service-members': {
      patterns: [
        { include: '#comments' },
        { include: '#const' },
        {
          name: 'meta.section.iface',
          begin: String.raw`${B}(${alt(SECTION_NAMES)})\s*(\{)`,
          beginCaptures: {
            1: { name: 'keyword.other.section.iface' },
            2: { name: 'punctuation.section.block.begin.iface' },
          },
          end: String.raw`\}`,
          endCaptures: { 0: { name: 'punctuation.section.block.end.iface' } },
          patterns: [{ include: '#members' }],
        },
        {
          name: 'meta.section.iface',
          begin: String.raw`${B}(${ID})\s*(\{)`,
          beginCaptures: {
            1: { name: 'entity.name.section.iface' },
            2: { name: 'punctuation.section.block.begin.iface' },
          },
          end: String.raw`\}`,
          endCaptures: { 0: { name: 'punctuation.section.block.end.iface' } },
          patterns: [{ include: '#members' }],
        },
        {
          name: 'meta.throws.iface',
          begin: String.raw`${B}(throws)\s*(\()`,
          beginCaptures: {
            1: { name: 'keyword.other.throws.iface' },
            2: { name: 'punctuation.definition.parameters.begin.iface' },
          },
          end: String.raw`\)`,
          endCaptures: { 0: { name: 'punctuation.definition.parameters.end.iface' } },
          patterns: [{ include: '#members' }],
        },
        {
          name: 'meta.function.iface',
          begin: String.raw`${B}(${ID})\s*(\()`,
          beginCaptures: {
            1: { name: 'entity.name.function.iface' },
            2: { name: 'punctuation.definition.parameters.begin.iface' },
          },
          end: String.raw`\)`,
          endCaptures: { 0: { name: 'punctuation.definition.parameters.end.iface' } },
          patterns: [{ include: '#members' }],
        },
        { name: 'keyword.other.throws.iface', match: String.raw`${B}throws${E}` },
        { name: 'storage.modifier.oneway.iface', match: String.raw`${B}oneway${E}` },
        { name: 'storage.type.void.iface', match: String.raw`${B}void${E}` },
        { include: '#members' },
        block('section', [{ include: '#members' }]),
      ],
    },
    members: {
      patterns: [
        { include: '#comments' },
        { include: '#const' },
        {
          match: String.raw`${B}([+-]?(?:0[xX][0-9A-Fa-f]+|[0-9]+))\s*(:)`,
          captures: {
            1: { name: 'constant.numeric.integer.field-id.iface' },
            2: { name: 'punctuation.separator.field-id.iface' },
          },
        },
        {
          name: 'variable.other.field.iface',
          match: String.raw`${B}${ID}${AFTER_NAME}`,
        },
        { name: 'storage.modifier.$1.iface', match: String.raw`${B}(required|optional)${E}` },
        { name: 'storage.modifier.reference.iface', match: '&' },
        { include: '#types' },
        { include: '#default-value' },
        { include: '#annotations' },
        { include: '#separators' },
      ],
    },

    // ---- Types -----------------------------------------------------------
    types: {
      patterns: [
        { include: '#comments' },
        { include: '#strings' },
        {
          match: String.raw`${B}(string|wstring)\s*(<=)\s*([+-]?(?:0[xX][0-9A-Fa-f]+|[0-9]+))${E}`,
          captures: {
            1: { name: 'support.type.primitive.iface' },
            2: { name: 'keyword.operator.bound.iface' },
            3: { patterns: [{ include: '#numbers' }] },
          },
        },
        { name: 'support.type.container.iface', match: String.raw`${B}(?:map|set|list)${E}` },
        { name: 'keyword.other.cpp-type.iface', match: String.raw`${B}cpp_type${E}` },
        {
          name: 'meta.type-arguments.iface',
          begin: '<(?!=)',
          beginCaptures: { 0: { name: 'punctuation.definition.typeparameters.begin.iface' } },
          end: '>',
          endCaptures: { 0: { name: 'punctuation.definition.typeparameters.end.iface' } },
          patterns: [
            { include: '#types' },
            { include: '#annotations' },
            { include: '#separators' },
          ],
        },
        {
          name: 'meta.array.iface',
          begin: String.raw`\[`,
          beginCaptures: { 0: { name: 'punctuation.definition.array.begin.iface' } },
          end: String.raw`\]`,
          endCaptures: { 0: { name: 'punctuation.definition.array.end.iface' } },
          patterns: [
            { name: 'keyword.operator.bound.iface', match: '<=' },
            { include: '#numbers' },
          ],
        },
        { name: 'support.type.primitive.iface', match: String.raw`${B}(?:${alt(BUILTIN_TYPES)})${E}` },
        { name: 'entity.name.type.iface', match: String.raw`${B}${QID}${E}` },
      ],
    },

    // ---- Values and annotations ------------------------------------------
    'default-value': {
      begin: '=',
      beginCaptures: { 0: { name: 'keyword.operator.assignment.iface' } },
      end: String.raw`(?=[,;()}]|$)`,
      patterns: [{ include: '#value' }],
    },
    value: {
      patterns: [
        { include: '#comments' },
        { include: '#strings' },
        { include: '#numbers' },
        {
          name: 'meta.list.iface',
          begin: String.raw`\[`,
          beginCaptures: { 0: { name: 'punctuation.definition.list.begin.iface' } },
          end: String.raw`\]`,
          endCaptures: { 0: { name: 'punctuation.definition.list.end.iface' } },
          patterns: [{ include: '#value' }, { include: '#separators' }],
        },
        {
          name: 'meta.map.iface',
          begin: String.raw`\{`,
          beginCaptures: { 0: { name: 'punctuation.definition.map.begin.iface' } },
          end: String.raw`\}`,
          endCaptures: { 0: { name: 'punctuation.definition.map.end.iface' } },
          patterns: [
            { include: '#value' },
            { name: 'punctuation.separator.key-value.iface', match: ':' },
            { include: '#separators' },
          ],
        },
        { name: 'variable.other.constant.iface', match: String.raw`${B}${QID}${E}` },
      ],
    },
    annotations: {
      name: 'meta.annotation.iface',
      begin: String.raw`\(`,
      beginCaptures: { 0: { name: 'punctuation.definition.annotation.begin.iface' } },
      end: String.raw`\)`,
      endCaptures: { 0: { name: 'punctuation.definition.annotation.end.iface' } },
      patterns: [
        { include: '#comments' },
        { include: '#default-value' },
        { name: 'entity.other.attribute-name.iface', match: String.raw`${B}${QID}${E}` },
        { include: '#separators' },
      ],
    },
  },
};

export function grammarJson() {
  return JSON.stringify(grammar, null, 2) + '\n';
}

const here = dirname(fileURLToPath(import.meta.url));
export const GRAMMAR_PATH = join(here, '..', 'syntaxes', 'iface.tmLanguage.json');

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  if (process.argv.includes('--check')) {
    let current = '';
    try {
      current = readFileSync(GRAMMAR_PATH, 'utf8');
    } catch {
      // missing: reported below
    }
    if (current !== grammarJson()) {
      console.error(`${GRAMMAR_PATH} is out of date: run \`node scripts/grammar.mjs\``);
      process.exit(1);
    }
    console.log(`${GRAMMAR_PATH} is up to date`);
  } else {
    writeFileSync(GRAMMAR_PATH, grammarJson());
    console.log(`wrote ${GRAMMAR_PATH}`);
  }
}
