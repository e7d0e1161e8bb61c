// Bundles src/main.js with three.js into ONE minified script (IIFE) for embedding in HTML pages.
//   usage: node build.mjs OUTPUT.js
import { build } from 'esbuild';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const output = process.argv[2] ?? join(here, 'dist', 'mocap-viewer.js');
await build({
  entryPoints: [join(here, 'src', 'main.js')],
  outfile: output,
  bundle: true,
  minify: true,
  format: 'iife',
  target: ['es2020'],
  charset: 'ascii',
  legalComments: 'eof',
  loader: { '.css': 'text' },
  logLevel: 'warning',
});
