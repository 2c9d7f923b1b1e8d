// bunny_to_obj.js - writes the Stanford bunny of the npm package "bunny" as an OBJ file for the tests.
// Usage: node bunny_to_obj.js OUT.obj   ("bunny" resolves from tests/data/node_modules, next to this script)
'use strict';

const fs = require('fs');

function main(argv) {
  if (argv.length !== 1) {
    process.stderr.write('usage: node bunny_to_obj.js OUT.obj\n');
    return 2;
  }
  const { positions, cells } = require('bunny');
  const lines = ['# Stanford bunny from the npm package "bunny" (public domain)'];
  for (const p of positions) lines.push(`v ${p[0]} ${p[1]} ${p[2]}`);
  // OBJ indices are 1-based; the package's cells are 0-based
  for (const c of cells) lines.push(`f ${c[0] + 1} ${c[1] + 1} ${c[2] + 1}`);
  fs.writeFileSync(argv[0], lines.join('\n') + '\n');
  process.stdout.write(`${argv[0]}: ${positions.length} vertices, ${cells.length} triangles\n`);
  return 0;
}

process.exitCode = main(process.argv.slice(2));
