#!/usr/bin/env bash
# Rewrites the README's table of option defaults (between its options-table markers) from
# `gazetrace options`, which reads the same CLI11 definitions that parse the command line.
# Usage: scripts/options_table.sh [path/to/gazetrace]   (default build/gazetrace)
set -euo pipefail
cd "$(dirname "$0")/.."
G=${1:-build/gazetrace}
table=$("$G" options)
python3 - "$table" <<'PY'
import sys
table = sys.argv[1].rstrip("\n") + "\n"
begin, end = "<!-- options-table -->\n", "<!-- /options-table -->"
s = open("README.md").read()
i, j = s.index(begin) + len(begin), s.index(end)
tmp = "README.md.options-table.tmp"
open(tmp, "w").write(s[:i] + table + s[j:])
import os; os.replace(tmp, "README.md")
PY
echo "README.md: options table regenerated from $G options"
