#!/usr/bin/env bash
# Hygiene check of the repository's text, run by ctest (docs_check, docs_check_self_test):
#  (a) history: comments and docs say what the code does and why, not when or on which machine.
#      Flags commit hashes, work-log markers (session/issue/stop numbers, § numbers), dates and
#      the names of the machines measurements were taken on. Scanned: README.md, CMakeLists.txt,
#      docs/ (not docs/journal/, the project's history), src/, apps/, configs/, scripts/ (not this
#      script or its allow file), tests/, lcmtypes/, plots/. Not scanned: CHANGELOG.md,
#      docs/journal/, experiments/ (history by design). docs/results.md quotes the provenance of
#      each figure in its tables, so its table rows (lines starting with '|') are exempt from the
#      hash, date and machine patterns, not from the work-log markers.
#  (b) links: every relative Markdown link or image in README.md, CHANGELOG.md,
#      experiments/README.md and docs/**/*.md names an existing file or folder (relative to the
#      linking file), and every #anchor into a .md file names one of its headings (GitHub's rule:
#      lower case, punctuation other than '-' and '_' dropped, spaces to '-', "-1", "-2" for
#      repeats) or an <a name/id> in it. http(s), mailto and other scheme links are skipped.
# Prints each finding as file:line: kind: text and exits 1 if there is any, 0 with a summary.
#   bash scripts/check_docs.sh [--root DIR]     check DIR (default: this script's repository)
#   bash scripts/check_docs.sh --self-test      plant one of each fault in a scratch tree and
#                                               check that each is reported (exit 0 if so)
# Allowed hits: scripts/check_docs.allow, one "PATH TEXT" per line (a hit in file PATH whose line
# contains TEXT is not reported), each with its reason in a comment line above it.
# Needs bash, coreutils, GNU grep, sed and awk only (any awk: no {m,n} in its regular expressions).
set -uo pipefail

# ---- (a) the history patterns: "class|name|extended regex" (grep -E, case-insensitive). ----
# class "log" applies everywhere; class "provenance" not in docs/results.md table rows.
# Commit hashes are found by the awk below (a word of 7-40 lower-case hex digits with at least one
# digit and one letter a-f, not a number such as 1234567e or 999999f), class "provenance".
PATTERNS=(
  # A work-log session number ("session 12", "sessions 32-33").
  'log|session|\<sessions? [0-9]+'
  # An issue-tracker number ("issue 18"), which says when a change came, not what the code does.
  'log|issue|\<issues? #?[0-9]+'
  # A section number of an issue or spec ("§3", "§ 4"); name the section instead.
  'log|section-number|§ ?[0-9]'
  # A numbered stop of a work log ("stop 3").
  'log|stop|\<stop [0-9]+'
  # A calendar date (2024-05-17).
  'provenance|date|\<20[0-9]{2}-[01][0-9]-[0-3][0-9]\>'
  # The CPU a measurement was taken on ("Zen 4").
  'provenance|machine|\<Zen [0-9]'
  # The virtual machine a measurement was taken on.
  'provenance|machine|AVX-512 VM|\<(the|this|these) VMs?\>'
  # CPU model strings as /proc/cpuinfo prints them.
  'provenance|machine|Intel\(R\)|\<EPYC\>|\<family [0-9]+ model\>'
)

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
self="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/$(basename "${BASH_SOURCE[0]}")"

# A UTF-8 locale, so that [[:alnum:]] in the anchor rule keeps letters such as θ and drops — and ±.
utf8=$(locale -a 2>/dev/null | grep -iE '^c\.utf-?8$' | head -1)
[ -n "$utf8" ] || utf8=$(locale -a 2>/dev/null | grep -iE '\.utf-?8$' | head -1)
export LC_ALL=${utf8:-C.UTF-8}

self_test() {
  local tmp out rc ok=1
  tmp=$(mktemp -d) || exit 2
  trap 'rm -rf "$tmp"' EXIT
  mkdir -p "$tmp/src" "$tmp/docs" "$tmp/scripts"
  printf '// Rounds the step to the grid.\n// Fixed in 3f9a2c1d after the review.\nint x = 0;\n' > "$tmp/src/a.cpp"
  printf '# Sizes of the mesh.\n# Measured in session 12.\nn = 3\n' > "$tmp/scripts/b.sh"
  printf '# T\n\nSee [the guide](docs/guide.md#the-first-step) and [gone](docs/missing.md).\n' > "$tmp/README.md"
  printf '# Guide\n\n## The first step\n\n| run | 3f9a2c1d |\n' > "$tmp/docs/guide.md"
  cp "$tmp/docs/guide.md" "$tmp/docs/results.md"
  out=$(bash "$self" --root "$tmp" 2>&1); rc=$?
  echo "$out"
  check() { if echo "$out" | grep -qF -- "$2"; then echo "self-test: $1: reported"; else echo "self-test: $1: NOT reported" >&2; ok=0; fi; }
  check "planted commit hash" "src/a.cpp:2: commit-hash:"
  check "planted session marker" "scripts/b.sh:2: session:"
  check "planted broken link" "README.md:3: broken link: docs/missing.md"
  # and nothing that is in order: the good anchor, the table row of docs/results.md
  if echo "$out" | grep -qF -e "docs/guide.md#the-first-step" -e "docs/results.md:5"; then
    echo "self-test: a correct link or an exempt table row was reported" >&2; ok=0
  fi
  [ "$rc" = 1 ] || { echo "self-test: exit $rc, expected 1" >&2; ok=0; }
  [ "$ok" = 1 ] && { echo "self-test: passed"; exit 0; }
  exit 1
}

root=$here
case "${1:-}" in
  --self-test) self_test ;;
  --root) root=$(cd "${2:?--root DIR}" && pwd) || exit 2 ;;
  "") ;;
  *) echo "usage: bash scripts/check_docs.sh [--root DIR | --self-test]" >&2; exit 2 ;;
esac
cd "$root" || exit 2
allow="$root/scripts/check_docs.allow"
[ -f "$allow" ] || allow=/dev/null

# ---- (a) history ----
scan=()
for p in README.md CMakeLists.txt; do [ -f "$p" ] && scan+=("$p"); done
for d in docs src apps configs scripts tests lcmtypes plots; do
  [ -d "$d" ] || continue
  while IFS= read -r f; do
    case "$f" in
      docs/journal/*|scripts/check_docs.sh|scripts/check_docs.allow) continue ;;
    esac
    scan+=("$f")
  done < <(find "$d" -type f | sort)
done
# text files only (grep -I drops binary ones)
mapfile -t scan < <(printf '%s\0' "${scan[@]}" | xargs -0 grep -Il '' -- 2>/dev/null)

hits() {  # file:line:class:name:text, one per hit
  local e class rest name re
  for e in "${PATTERNS[@]}"; do
    class=${e%%|*}; rest=${e#*|}; name=${rest%%|*}; re=${rest#*|}
    grep -nHiE -- "$re" "${scan[@]}" 2>/dev/null | sed -E "s/^([^:]*):([0-9]+):/\1:\2:$class:$name:/"
  done
  awk '{
    l = $0; gsub(/[^0-9A-Za-z_]/, " ", l); n = split(l, w, " ")
    for (i = 1; i <= n; ++i) {
      t = w[i]
      if (length(t) < 7 || length(t) > 40 || t !~ /^[0-9a-f]+$/ || t !~ /[0-9]/ || t !~ /[a-f]/) continue
      if (t ~ /^[0-9]+[a-f]$/ || t ~ /^[0-9]+e[0-9]+$/) continue  # 1234567e-3, 999999f, 12e345678
      print FILENAME ":" FNR ":provenance:commit-hash:" $0; break
    }
  }' "${scan[@]}"
}
history_out=$(hits | awk -v allow="$allow" '
  BEGIN {
    while ((getline a < allow) > 0) {
      if (a ~ /^[ \t]*(#|$)/) continue
      sp = index(a, " "); if (sp == 0) continue
      na++; apath[na] = substr(a, 1, sp - 1); atext[na] = substr(a, sp + 1)
    }
  }
  {
    # file:line:class:name:text (the file names scanned hold no colon)
    f = $0; i = index(f, ":"); file = substr(f, 1, i - 1); f = substr(f, i + 1)
    i = index(f, ":"); line = substr(f, 1, i - 1); f = substr(f, i + 1)
    i = index(f, ":"); class = substr(f, 1, i - 1); f = substr(f, i + 1)
    i = index(f, ":"); name = substr(f, 1, i - 1); text = substr(f, i + 1)
    if (file == "docs/results.md" && class == "provenance" && text ~ /^[ \t]*\|/) next
    for (k = 1; k <= na; ++k) if (file == apath[k] && index(text, atext[k]) > 0) next
    key = file ":" line ":" name; if (key in seen) next; seen[key] = 1
    sub(/^[ \t]+/, "", text); if (length(text) > 200) text = substr(text, 1, 197) "..."
    print file ":" line ": " name ": " text
  }' | sort -t: -k1,1 -k2,2n)

# ---- (b) links ----
# Headings of a Markdown file as GitHub's anchors, one per line (outside fenced code blocks), and
# the names of its <a name=...>/<a id=...> anchors.
anchors_of() {
  awk '
    /^[ \t]*(```|~~~)/ { fence = !fence; next }
    fence { next }
    /^#+[ \t]/ && match($0, /^#+/) && RLENGTH <= 6 { h = $0; sub(/^#+[ \t]+/, "", h); sub(/[ \t]+#+[ \t]*$/, "", h); print "H" h }
    {
      l = $0
      while (match(l, /<a[ \t]+(name|id)="[^"]+"/)) {
        a = substr(l, RSTART, RLENGTH); sub(/^[^"]*"/, "", a); sub(/"$/, "", a); print "A" a
        l = substr(l, RSTART + RLENGTH)
      }
    }' "$1" |
  sed -E '/^H/ { s/!?\[([^]]*)\]\([^)]*\)/\1/g; s/<[^>]+>//g; s/^H[[:space:]]*//; s/[[:space:]]+$//;
                 s/.*/\L&/; s/[^[:alnum:]_ -]//g; s/ /-/g; s/^/H/ }' |
  awk '/^H/ { s = substr($0, 2); if (s in n) { print s "-" n[s]; n[s]++ } else { print s; n[s] = 1 } next }
       { print substr($0, 2) }'
}

# Links of a Markdown file: "line<TAB>target", outside fenced code blocks and inline code spans;
# inline links and images [text](target "title") and reference definitions [ref]: target.
links_of() {
  awk '
    /^[ \t]*(```|~~~)/ { fence = !fence; next }
    fence { next }
    {
      l = $0; gsub(/`[^`]*`/, "", l)
      if (match(l, /^ ? ? ?\[[^]]+\]:[ \t]+[^ \t]+/)) {
        t = substr(l, RSTART, RLENGTH); sub(/^[^]]*\]:[ \t]+/, "", t); print FNR "\t" t; next
      }
      while (match(l, /\]\([^)]*\)/)) {
        t = substr(l, RSTART + 2, RLENGTH - 3); l = substr(l, RSTART + RLENGTH)
        sub(/^[ \t]+/, "", t); sub(/[ \t]+("[^"]*"|'"'"'[^'"'"']*'"'"')?[ \t]*$/, "", t)
        sub(/^</, "", t); sub(/>$/, "", t)
        if (t != "") print FNR "\t" t
      }
    }' "$1"
}

md=()
for p in README.md CHANGELOG.md experiments/README.md; do [ -f "$p" ] && md+=("$p"); done
[ -d docs ] && while IFS= read -r f; do md+=("$f"); done < <(find docs -type f -name '*.md' | sort)
declare -A anchor_cache
link_out=""
for f in "${md[@]}"; do
  dir=$(dirname "$f")
  while IFS=$'\t' read -r line target; do
    case "$target" in
      [A-Za-z]*:*) [[ "$target" =~ ^[A-Za-z][A-Za-z0-9+.-]*: ]] && continue ;;
    esac
    path=${target%%#*}; anchor=""
    [ "$path" = "$target" ] || anchor=${target#*#}
    path=${path//%20/ }
    if [ -z "$path" ]; then dest=$f; else dest="$dir/$path"; fi
    if [ ! -e "$dest" ]; then
      link_out+="$f:$line: broken link: $target (no ${dest#./})"$'\n'; continue
    fi
    [ -n "$anchor" ] || continue
    case "$dest" in *.md) ;; *) continue ;; esac
    [ -f "$dest" ] || continue
    key=$(realpath -m "$dest")
    [ -n "${anchor_cache[$key]+x}" ] || anchor_cache[$key]=$'\n'"$(anchors_of "$dest")"$'\n'
    want=$(printf '%s' "$anchor" | sed -E 's/.*/\L&/')
    case "${anchor_cache[$key]}" in
      *$'\n'"$want"$'\n'*) ;;
      *) link_out+="$f:$line: broken anchor: $target (no heading #$anchor in ${dest#./})"$'\n' ;;
    esac
  done < <(links_of "$f")
done
link_out=${link_out%$'\n'}

nh=0; nl=0
[ -z "$history_out" ] || { echo "$history_out"; nh=$(echo "$history_out" | wc -l); }
[ -z "$link_out" ] || { echo "$link_out"; nl=$(echo "$link_out" | wc -l); }
if [ "$nh" -gt 0 ] || [ "$nl" -gt 0 ]; then
  echo "check_docs: $nh history hit(s) in ${#scan[@]} files, $nl broken link(s) in ${#md[@]} Markdown files" >&2
  exit 1
fi
echo "check_docs: ${#scan[@]} files free of history patterns, ${#md[@]} Markdown files' links resolve"
exit 0
