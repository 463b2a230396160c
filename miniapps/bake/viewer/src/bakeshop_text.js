// Streaming reader of Bake Shop text maps (.bs) with the C++ reader's rules and messages
// (common/src/io/bakeshop_reader.cpp, docs/architecture.md section 5): feed text chunks with
// push(), then finish(). Errors are BakeshopError "name:line: reason".
import { Growable } from './growable.js';
import { MapBuilder } from './map_data.js';

export class BakeshopError extends Error {
  constructor(name, line, reason) {
    super(line > 0 ? `${name}:${line}: ${reason}` : `${name}: ${reason}`);
    this.line = line;
    this.reason = reason;
  }
}

// std::from_chars accepts these (plus a leading '+' as strtod does); anything else is
// "invalid number", and inf/nan are "non-finite", as in the C++ reader.
const kDecimal = /^[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?$/;
const kNonFinite = /^[+-]?(?:inf(?:inity)?|nan(?:\([A-Za-z0-9_]*\))?)$/i;
const kInteger = /^[+-]?\d+$/;
const kMaxFloat = 3.4028234663852886e38;

const kVertices = 0;
const kMaterials = 1;
const kFaces = 2;
const kDone = 3;

function splitFields(line) {
  const fields = line.split(/[ \t\r]+/);
  if (fields.length && fields[0] === '') fields.shift();
  if (fields.length && fields[fields.length - 1] === '') fields.pop();
  return fields;
}

export class BakeshopTextParser {
  constructor(name) {
    this.name = name;
    this.section = kVertices;
    this.lineNumber = 0;
    this.rest = '';
    this.builder = new MapBuilder();
    this.materials = new Growable(Float32Array, 64);
    this.faces = new Growable(Int32Array, 1024);
  }

  fail(reason, line = this.lineNumber) {
    throw new BakeshopError(this.name, line, reason);
  }

  push(text) {
    const parts = (this.rest + text).split('\n');
    this.rest = parts.pop();
    for (const line of parts) this.line(line);
  }

  finish() {
    if (this.rest !== '') this.line(this.rest);
    this.rest = '';
    if (this.lineNumber === 0)
      this.fail("empty file (expected vertices, materials, faces and a final '!')", 1);
    if (this.section !== kDone) this.fail("missing '!' at end of file");
    return this.builder.finish(this.materials.take(), this.faces.take());
  }

  line(raw) {
    ++this.lineNumber;
    const line = raw.replace(/\r$/, '').replace(/^[ \t]+/, '');
    const fields = splitFields(line);
    const blank = fields.length === 0;
    if (this.section === kDone) {
      if (!blank) this.fail("unexpected content after the final '!'");
      return;
    }
    if (blank) {
      if (this.section === kFaces) this.fail('blank line inside the faces section');
      if (this.section === kVertices) this.builder.endVertices();
      ++this.section;
      return;
    }
    const first = line[0];
    // bake --directions hemisphere: directions in each vertex's frame (../README.md).
    if (first === '#' && this.lineNumber === 1 && fields.join(' ') === '# hemisphere')
      this.fail('a hemisphere map (bake --directions hemisphere): this viewer reads full-sphere maps only');
    if (first === '!') {
      if (splitFields(line.slice(1)).length) this.fail("unexpected content after '!'");
      if (this.section !== kFaces)
        this.fail("'!' before the faces section (sections are separated by one blank line)");
      this.section = kDone;
      return;
    }
    if (this.section === kVertices) {
      if (first === '|') this.viewpoint(splitFields(line.slice(1)));
      else if (first === ':') this.fail('material line in the vertices section (missing blank line?)');
      else this.vertex(fields);
    } else if (this.section === kMaterials) {
      if (first !== ':') this.fail("expected a material line ': dr dg db  sr sg sb  er eg eb'");
      this.material(splitFields(line.slice(1)));
    } else {
      this.face(fields);
    }
  }

  real(field, what, isFloat) {
    if (kNonFinite.test(field)) this.fail(`non-finite value '${field}' in ${what}`);
    if (!kDecimal.test(field) || field.startsWith('+-')) this.fail(`invalid number '${field}' in ${what}`);
    const value = Number(field);
    // Out of the type's range: from_chars reports result_out_of_range.
    if (!Number.isFinite(value) || (isFloat && Math.abs(value) > kMaxFloat))
      this.fail(`invalid number '${field}' in ${what}`);
    return isFloat ? Math.fround(value) : value;
  }

  integer(field, what) {
    if (!kInteger.test(field) || field.startsWith('+-')) this.fail(`invalid number '${field}' in ${what}`);
    return Number(field);
  }

  expectFields(fields, n, what) {
    if (fields.length !== n) this.fail(`${what} needs ${n} fields, got ${fields.length}`);
  }

  vertex(f) {
    this.expectFields(f, 3, 'vertex');
    this.builder.addVertex(
      this.real(f[0], 'vertex', false),
      this.real(f[1], 'vertex', false),
      this.real(f[2], 'vertex', false),
    );
  }

  viewpoint(f) {
    if (this.builder.vertexCount === 0) this.fail('viewpoint line before any vertex');
    this.expectFields(f, 6, "viewpoint '| dx dy dz r g b'");
    const v = f.map((x) => this.real(x, 'viewpoint', true));
    this.builder.addViewpoint(v[0], v[1], v[2], v[3], v[4], v[5]);
  }

  material(f) {
    this.expectFields(f, 9, "material ': dr dg db  sr sg sb  er eg eb'");
    for (const x of f) this.materials.push(this.real(x, 'material', true));
  }

  face(f) {
    if (f.length !== 4 && f.length !== 5)
      this.fail(`face needs 3 or 4 vertex indices and a material index, got ${f.length} fields`);
    const count = f.length - 1;
    const nv = this.builder.vertexCount;
    this.faces.reserve(5);
    for (let k = 0; k < 4; ++k) {
      if (k >= count) {
        this.faces.push(-1);
        continue;
      }
      const index = this.integer(f[k], 'face');
      if (index < 0 || index >= nv) this.fail(`vertex index ${index} out of range [0, ${nv})`);
      this.faces.push(index);
    }
    const material = this.integer(f[count], 'face');
    const nm = this.materials.length / 9;
    if (material < -1 || material >= nm)
      this.fail(`material index ${material} out of range [-1, ${nm})`);
    this.faces.push(material);
  }
}
