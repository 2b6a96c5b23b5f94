#!/usr/bin/env bash
# Fetches the Stanford bunny (1,839 vertices, 3,674 triangles) from the npm
# registry package `bunny` 1.0.1 (Mikola Lysenko; marked "Public Domain"
# there; the scan is from the Stanford 3D Scanning Repository,
# http://graphics.stanford.edu/data/3Dscanrep/, which asks users to credit
# it) and writes it as an OBJ to scenes/meshes/bunny.obj (not committed:
# see .gitignore). Needs npm and node. The benchmark scenes and examples
# that use the bunny say so and skip without it.
set -euo pipefail
cd "$(dirname "$0")/.."
out=scenes/meshes/bunny.obj
if [ -s "$out" ]; then echo "$out is there"; exit 0; fi
command -v npm >/dev/null && command -v node >/dev/null || { echo "fetch-bunny needs npm and node" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
(cd "$work" && npm pack --silent bunny@1.0.1 >/dev/null && tar xzf bunny-1.0.1.tgz)
node -e '
const b = require(process.argv[1]);
const lines = ["# The Stanford bunny: npm package bunny 1.0.1 (Mikola Lysenko), from the",
  "# Stanford 3D Scanning Repository (http://graphics.stanford.edu/data/3Dscanrep/).",
  "# Converted by scripts/fetch-bunny.sh; coordinates as in the package."];
for (const p of b.positions) lines.push("v " + p.join(" "));
for (const c of b.cells) lines.push("f " + c.map(i => i + 1).join(" "));
process.stdout.write(lines.join("\n") + "\n");
' "$work/package" > "$out.tmp"
mv "$out.tmp" "$out"
echo "wrote $out ($(grep -c '^f ' "$out") triangles)"
