// Builds the viewer into one self-contained HTML file: esbuild bundles src/main.js (three.js,
// uPlot and our code), then the script and the styles are inlined into src/index.html.
//   node tools/build.mjs OUT.html [NODE_MODULES_DIR]
import { createRequire } from 'node:module';
import { readFileSync, writeFileSync, mkdirSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = resolve(dirname(fileURLToPath(import.meta.url)), '..');
const [out, modulesArg] = process.argv.slice(2);
if (!out) {
  console.error('usage: node tools/build.mjs OUT.html [NODE_MODULES_DIR]');
  process.exit(2);
}
const modules = resolve(modulesArg || join(root, 'node_modules'));
const require = createRequire(join(modules, 'noop.js'));
const esbuild = require('esbuild');

const result = await esbuild.build({
  entryPoints: [join(root, 'src/main.js')],
  bundle: true,
  minify: true,
  format: 'iife',
  target: 'es2020',
  write: false,
  nodePaths: [modules],
  legalComments: 'none',
  logLevel: 'warning',
});
// An inline script ends at the first "</script": never let the bundle contain one.
const js = result.outputFiles[0].text.replaceAll('</script', '<\\/script');
const css = readFileSync(join(modules, 'uplot/dist/uPlot.min.css'), 'utf8') + readFileSync(join(root, 'src/style.css'), 'utf8');
const html = readFileSync(join(root, 'src/index.html'), 'utf8')
  .replace('/*GRIP-STYLE*/', () => css)
  .replace('/*GRIP-SCRIPT*/', () => js);
mkdirSync(dirname(resolve(out)), { recursive: true });
writeFileSync(out, html);
console.log(`viewer: ${out} (${(html.length / 1024).toFixed(0)} KiB)`);
