// Builds the page into dist/: src/main.js and three.js bundled into one
// classic script (so dist/index.html also opens from disk), the HTML and CSS
// copied beside it. Nothing is fetched: everything comes from node_modules.

import { build } from 'esbuild';
import { copyFileSync, mkdirSync, rmSync } from 'node:fs';

const here = (path) => new URL(path, import.meta.url);

rmSync(here('dist'), { recursive: true, force: true });
mkdirSync(here('dist'));
await build({
  entryPoints: [here('src/main.js').pathname],
  outfile: here('dist/viewer.js').pathname,
  bundle: true,
  format: 'iife',
  target: 'es2022',
  minify: true,
  sourcemap: true,
  legalComments: 'linked',
  logLevel: 'warning',
});
copyFileSync(here('index.html'), here('dist/index.html'));
copyFileSync(here('src/style.css'), here('dist/style.css'));
console.log('viewer built into dist/');
