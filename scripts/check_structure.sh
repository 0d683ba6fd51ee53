#!/usr/bin/env bash
# Structure check of the sources, run by ctest (structure_check):
#  (a) modules: a module is a header and its source file (src/run/run.hpp + run.cpp); a private
#      header X_impl.hpp belongs to module X. An #include of a project header makes its module
#      depend on the header's module. The graph over all
#      modules of src/ must have no cycle (tsort), so no header of a lower file reaches into a
#      file that uses it.
#  (b) the run's hub: src/run/run.hpp is included only by src/run/run.cpp and by apps/.
#  (c) functions: no function body in src/ or apps/ longer than 120 lines, except those named
#      in scripts/check_structure.allow ("PATH FUNCTION" per line, each with its reason above it).
# Prints each finding as file:line: kind: text and exits 1 if there is any, 0 with a summary.
#   bash scripts/check_structure.sh [--root DIR]
#   bash scripts/check_structure.sh --list-functions N   print every function longer than N lines
#   bash scripts/check_structure.sh --self-test   plant a module cycle, a hub include and a long
#                                                 function in a scratch tree and check that each
#                                                 is reported (exit 0 if so)
# Needs bash, coreutils (tsort), GNU grep, sed and awk only.
set -uo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
list_over=""
while [ $# -gt 0 ]; do
  case "$1" in
    --root) root="$2"; shift 2 ;;
    --list-functions) list_over="$2"; shift 2 ;;
    --self-test)
      scratch=$(mktemp -d)
      trap 'rm -rf "$scratch"' EXIT
      mkdir -p "$scratch/src/a" "$scratch/src/b" "$scratch/src/run" "$scratch/apps" "$scratch/scripts"
      printf '#pragma once\n#include "b/y.hpp"\n' > "$scratch/src/a/x.hpp"
      printf '#pragma once\n' > "$scratch/src/b/y.hpp"
      printf '#include "b/y.hpp"\n#include "a/x.hpp"\n' > "$scratch/src/b/y.cpp"
      printf '#pragma once\n' > "$scratch/src/run/run.hpp"
      printf '#include "run/run.hpp"\n' > "$scratch/src/run/other.cpp"
      { printf 'int long_one(int a) {\n'; for _ in $(seq 1 125); do printf '  a += 1;  // {\n'; done
        printf '  return a;\n}\nint short_one() {\n  return 0;\n}\n'; } > "$scratch/apps/f.cpp"
      out=$(bash "${BASH_SOURCE[0]}" --root "$scratch")
      ok=1
      for want in "module cycle: src/a/x src/b/y" "src/run/other.cpp:1: hub" "apps/f.cpp:1: function: long_one is 128 lines"; do
        if ! grep -qF "$want" <<< "$out"; then echo "check_structure self-test: not reported: $want"; ok=0; fi
      done
      if grep -q short_one <<< "$out"; then echo "check_structure self-test: short_one reported"; ok=0; fi
      [ "$ok" = 1 ] && { echo "check_structure self-test: all 3 planted faults reported"; exit 0; }
      echo "$out"; exit 1 ;;
    *) echo "check_structure: unknown argument $1" >&2; exit 2 ;;
  esac
done
cd "$root" || exit 2
max_lines=120
findings=0
report() { echo "$1"; findings=$((findings + 1)); }

# Function bodies: a line that ends a function's signature with "{" (it has a ')' and is not a
# control statement, a class, a namespace or an initialiser) at a depth where no function is open,
# then lines until its braces close. Comments and string and character literals are stripped
# first, so braces inside them do not count.
function_lengths() {
  awk -v over="$1" '
    function strip(s,   out, i, c, n) {
      out = ""; n = length(s)
      for (i = 1; i <= n; i++) {
        c = substr(s, i, 1)
        if (in_block) { if (c == "*" && substr(s, i + 1, 1) == "/") { in_block = 0; i++ } continue }
        if (c == "/" && substr(s, i + 1, 1) == "/") break
        if (c == "/" && substr(s, i + 1, 1) == "*") { in_block = 1; i++; continue }
        # A quote after a digit is a digit separator, not a character literal.
        if (c == "\"" || (c == "\047" && substr(s, i - 1, 1) !~ /[0-9A-Fa-f]/)) {
          q = c; i++
          while (i <= n && substr(s, i, 1) != q) { if (substr(s, i, 1) == "\\") i++; i++ }
          out = out q q; continue
        }
        out = out c
      }
      return out
    }
    FNR == 1 { depth = 0; fdepth = -1; in_block = 0; sig = "" }
    {
      line = strip($0)
      if (fdepth < 0) {
        t = line; gsub(/^[ \t]+/, "", t)
        if (t ~ /^#/) next
        sig = (sig == "" ? t : sig " " t)
        if (length(sig) > 600) sig = substr(sig, length(sig) - 600)
      }
      opens = gsub(/\{/, "{", line); closes = gsub(/\}/, "}", line)
      if (fdepth < 0 && opens > closes && sig ~ /\)[^;{}]*\{[^{}]*$/ &&
          sig !~ /(^|[^A-Za-z_])(if|for|while|switch|catch|do|else|namespace|struct|class|enum|union)([^A-Za-z_]|$)[^()]*\{[^{}]*$/ &&
          sig !~ /=[ \t]*\{[^{}]*$/ && sig !~ /\[[^]]*\][^()]*\([^()]*\)[^{}]*\{[^{}]*$/) {
        name = sig; sub(/\(.*/, "", name); n2 = split(name, parts, /[ \t*&]+/); name = parts[n2]
        fdepth = depth; fstart = FNR; fname = name
      }
      depth += opens - closes
      if (fdepth < 0 && (opens > 0 || closes > 0 || line ~ /;[ \t]*$/)) sig = ""
      if (fdepth >= 0 && depth <= fdepth) {
        len = FNR - fstart + 1
        if (len > over) print FILENAME ":" fstart ": " fname " " len
        fdepth = -1; sig = ""
      }
    }' $(find src apps -name '*.cpp' -o -name '*.hpp' | sort)
}

if [ -n "$list_over" ]; then
  function_lengths "$list_over" | sort -t' ' -k3 -n -r
  exit 0
fi

# (a) module graph.
edges=$(mktemp)
trap 'rm -f "$edges"' EXIT
for f in $(find src -name '*.cpp' -o -name '*.hpp' | sort); do
  mod="${f%.*}"
  mod="${mod%_impl}"
  echo "$mod $mod" >> "$edges"
  grep -oE '^#include "[a-z_]+/[a-z0-9_]+\.hpp"' "$f" | sed -E 's/^#include "(.*)\.hpp"/src\/\1/; s/_impl$//' |
    while read -r dep; do [ "$dep" != "$mod" ] && echo "$dep $mod"; done >> "$edges"
done
if ! loop=$(tsort "$edges" 2>&1 >/dev/null) || [ -n "$loop" ]; then
  report "src: module cycle: $(echo "$loop" | grep -v 'input contains a loop' | sed 's/^tsort: //' | tr '\n' ' ')"
fi

# (b) the hub.
while IFS=: read -r file lineno _; do
  case "$file" in src/run/run.cpp | apps/*) ;; *) report "$file:$lineno: hub: includes run/run.hpp" ;; esac
done < <(grep -rn '^#include "run/run.hpp"' src apps)

# (c) long functions.
allow="scripts/check_structure.allow"
while read -r where name len; do
  file="${where%%:*}"
  if [ -f "$allow" ] && grep -v '^#' "$allow" | grep -qxF "$file $name"; then continue; fi
  report "$where function: $name is $len lines (at most $max_lines)"
done < <(function_lengths "$max_lines")

if [ "$findings" -gt 0 ]; then
  echo "check_structure: $findings finding(s)"
  exit 1
fi
echo "check_structure: module graph acyclic, run/run.hpp only in run.cpp and apps/, no function over $max_lines lines but the allowed"
