#!/bin/bash
# test_docs_cli.sh: the documentation keeps up with the program. Every long
# option that `accelbench --help` and `accelbench COMMAND --help` print is
# listed in docs/cli.md; README.md fits on a screen (at most 150 lines);
# README.md and docs/ say what and why, not which issue or stop asked for it;
# every relative link of README.md and docs/**/*.md names a file that exists
# (docs/accels/ and docs/report.md are written alongside and are checked
# only when present). Prints "N passed, N failed"; exits 1 on a failure.
set -u
AB=${ACCELBENCH:?set ACCELBENCH to the accelbench binary}
SRC=${SRCDIR:-$(cd "$(dirname "$0")/.." && pwd)}
. "$(dirname "$0")/cli_lib.sh"
CLI=$SRC/docs/cli.md

# --- every option of every --help is in docs/cli.md
if [ ! -f "$CLI" ]; then
    bad "no docs/cli.md"
else
    top=$("$AB" --help 2>&1)
    # The commands: the lines of the top-level help that start with two spaces and a name.
    cmds=$(sed -nE 's/^  ([a-z]+)( .*)?$/\1/p' <<<"$top" | sort -u)
    [ "$(wc -w <<<"$cmds")" -ge 5 ] && ok || bad "found only these commands in accelbench --help: $cmds"
    helps=$top
    for c in $cmds; do
        h=$("$AB" "$c" --help 2>&1); rc=$?
        [ "$rc" = 0 ] && ok || bad "accelbench $c --help exited $rc"
        grep -qE "(^|[^a-z])$c([^a-z]|$)" "$CLI" && ok || bad "docs/cli.md does not name the command $c"
        helps+=$'\n'"$h"
    done
    opts=$(grep -oE -- '--[a-z][a-z0-9-]*' <<<"$helps" | sort -u)
    [ "$(wc -w <<<"$opts")" -ge 20 ] && ok || bad "found only these options in the help texts: $opts"
    missing=""
    for o in $opts; do
        grep -qE -- "(^|[^a-z0-9-])$o([^a-z0-9-]|$)" "$CLI" || missing+=" $o"
    done
    [ -z "$missing" ] && ok || bad "docs/cli.md lacks options that --help prints:$missing"
fi

# --- README.md fits on a screen
n=$(wc -l < "$SRC/README.md")
[ "$n" -le 150 ] && ok || bad "README.md has $n lines (at most 150)"

# --- no history in README.md and docs/
hist=$(grep -rnEi 'issue [0-9]|stop [0-9]' "$SRC/README.md" "$SRC/docs" 2>/dev/null)
[ -z "$hist" ] && ok || bad "README.md or docs/ refer to issues or stops: $hist"

# --- relative links name files that exist
broken=$(python3 - "$SRC" <<'PY'
import os, re, sys
src = sys.argv[1]
files = [os.path.join(src, "README.md")]
for root, _, names in os.walk(os.path.join(src, "docs")):
    files += [os.path.join(root, n) for n in names if n.endswith(".md")]
link = re.compile(r"!?\[[^\]]*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
later = (os.path.join(src, "docs", "accels") + os.sep, os.path.join(src, "docs", "report.md"))
for f in sorted(files):
    text = re.sub(r"```.*?```", "", open(f, encoding="utf-8").read(), flags=re.S)
    for m in link.finditer(text):
        t = m.group(1)
        if re.match(r"^[a-z][a-z0-9+.-]*:", t) or t.startswith("#"):
            continue
        path = os.path.normpath(os.path.join(os.path.dirname(f), t.split("#")[0]))
        if os.path.exists(path):
            continue
        if path.startswith(later[0]) or path == later[1]:
            continue  # written alongside; checked once present
        print(f"{os.path.relpath(f, src)}: {t}")
PY
)
[ -z "$broken" ] && ok || bad "broken relative links: $broken"

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
