// Compiles every generated WGSL file with Dawn (Chrome's WebGPU, through
// the npm package `webgpu`: dawn.node) and builds a pipeline for every
// entry point under WebGPU's default limits; fails on any compilation
// error or warning and any pipeline validation error. With `--compat`
// the render entries are also built on a compatibility-mode device
// (`featureLevel: 'compatibility'`), which the entries that need core
// WebGPU are allowed to fail, as generated/README.md lists them.
//
// Usage: node check.mjs [--compat] DIR_WITH_WGSL
// Dawn's backend comes from DAWN_OPTS (e.g. `backend=null`: Dawn's null
// backend validates without a GPU; the default picks the machine's).
import { create, globals } from 'webgpu';
import { readdirSync, readFileSync } from 'node:fs';
import { join } from 'node:path';

Object.assign(globalThis, globals);

const args = process.argv.slice(2);
const compat = args.includes('--compat');
const dir = args.filter((a) => !a.startsWith('--'))[0];
if (!dir) {
  console.error('usage: node check.mjs [--compat] DIR_WITH_WGSL');
  process.exit(2);
}
const opts = (process.env.DAWN_OPTS ?? '').split(',').filter((s) => s.length > 0);
const gpu = create(opts);

/** Entry points of a WGSL source: `{stage, name}` in source order. */
function entryPoints(code) {
  const re = /@(compute|vertex|fragment)\b[^\n]*\n\s*fn\s+(\w+)/g;
  const out = [];
  for (const m of code.matchAll(re)) out.push({ stage: m[1], name: m[2] });
  return out;
}

async function device(featureLevel) {
  const adapter = await gpu.requestAdapter({ featureLevel });
  if (!adapter) throw new Error(`no ${featureLevel} adapter (DAWN_OPTS=${opts.join(',')})`);
  // Default limits: no requiredLimits, no features.
  const dev = await adapter.requestDevice();
  const info = adapter.info ?? {};
  const name = [info.vendor, info.architecture, info.device, info.description]
    .filter((x) => x)
    .join(' ');
  return { dev, name: name || `(unnamed adapter, DAWN_OPTS=${opts.join(',')})` };
}

/**
 * A vertex module that only returns the file's `VsOut` (zeroed): the
 * fragment entries' compatibility check, apart from the real vertex
 * entries (which read storage buffers: core WebGPU only).
 */
function stubVertex(dev, code) {
  const m = code.match(/struct VsOut \{[^}]*\}/);
  if (!m) return null;
  return dev.createShaderModule({
    code: `${m[0]}\n@vertex fn stub_vs() -> VsOut { var o: VsOut; return o; }\n`,
  });
}

async function pipeline(dev, module, e, vertex) {
  dev.pushErrorScope('validation');
  if (e.stage === 'compute') {
    dev.createComputePipeline({ layout: 'auto', compute: { module, entryPoint: e.name } });
  } else {
    const desc = {
      layout: 'auto',
      vertex: e.stage === 'vertex' ? { module, entryPoint: e.name } : vertex,
      primitive: { topology: 'triangle-list' },
      depthStencil: { format: 'depth32float', depthWriteEnabled: true, depthCompare: 'less' },
    };
    if (e.stage === 'fragment') {
      desc.fragment = { module, entryPoint: e.name, targets: [{ format: 'rgba8unorm' }] };
    }
    dev.createRenderPipeline(desc);
  }
  const err = await dev.popErrorScope();
  return err ? err.message : null;
}

const files = readdirSync(dir).filter((f) => f.endsWith('.wgsl')).sort();
if (files.length === 0) {
  console.error(`no .wgsl files in ${dir}`);
  process.exit(1);
}
const core = await device('core');
const compatDev = compat ? await device('compatibility') : null;
console.log(`dawn: ${core.name}; ${files.length} files`);
let failures = 0;
let entries = 0;
const compatFailures = [];
for (const f of files) {
  const code = readFileSync(join(dir, f), 'utf8');
  const eps = entryPoints(code);
  const firstVertex = eps.find((e) => e.stage === 'vertex')?.name;
  for (const [label, d] of [['core', core.dev], ['compat', compatDev?.dev]]) {
    if (!d) continue;
    d.pushErrorScope('validation');
    const module = d.createShaderModule({ code, label: f });
    const info = await module.getCompilationInfo();
    const scopeErr = await d.popErrorScope();
    for (const m of info.messages) {
      if (m.type === 'error' || m.type === 'warning') {
        console.log(`${label} ${f}:${m.lineNum}:${m.linePos}: ${m.type}: ${m.message}`);
        if (label === 'core') failures++;
        else compatFailures.push(`${f}: module: ${m.message}`);
      }
    }
    if (scopeErr) {
      console.log(`${label} ${f}: ${scopeErr.message}`);
      if (label === 'core') failures++;
      continue;
    }
    // Fragment entries run behind the file's first vertex entry on the
    // core device, behind a stub returning the same `VsOut` in compat.
    const vertex =
      label === 'core'
        ? { module, entryPoint: firstVertex }
        : { module: stubVertex(d, code), entryPoint: 'stub_vs' };
    for (const e of eps) {
      if (label === 'core') entries++;
      const err = await pipeline(d, module, e, vertex);
      if (err) {
        const line = `${f} ${e.stage} ${e.name}: ${err.split('\n')[0]}`;
        if (label === 'core') {
          console.log(`core FAIL ${line}\n${err}`);
          failures++;
        } else {
          compatFailures.push(line);
        }
      }
    }
  }
}
console.log(`core: ${entries} entry points, ${failures} failures`);
if (compat) {
  console.log(`compat: ${compatFailures.length} entry points need core WebGPU:`);
  for (const l of compatFailures) console.log(`  ${l}`);
}
process.exit(failures === 0 ? 0 : 1);
