#!/bin/sh
# Regenerate the README's scene reference from `nct describe --markdown`
# (between the scene-reference markers), or with --check fail if it is stale.
# Usage: scripts/scene-reference.sh [--check] [path/to/nct]
set -eu
check=0
[ "${1:-}" = "--check" ] && { check=1; shift; }
nct=${1:-build/nct}
readme=README.md
begin='<!-- scene-reference:begin -->'
end='<!-- scene-reference:end -->'
table=$(mktemp)
new=$(mktemp)
trap 'rm -f "$table" "$new"' EXIT
"$nct" describe --markdown > "$table"
awk -v b="$begin" -v e="$end" -v t="$table" '
  $0 == b { print; while ((getline line < t) > 0) print line; skip = 1; next }
  $0 == e { skip = 0 }
  !skip { print }' "$readme" > "$new"
if [ "$check" -eq 1 ]; then
  if cmp -s "$readme" "$new"; then echo "README scene reference is up to date"; exit 0; fi
  echo "README scene reference is stale: run scripts/scene-reference.sh"; diff "$readme" "$new" | head -20
  exit 1
fi
cp "$new" "$readme"
echo "updated the scene reference in $readme"
