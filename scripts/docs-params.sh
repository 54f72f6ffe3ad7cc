#!/bin/bash
# docs-params.sh: the parameter sections of docs/accels/*.md, generated from
# the accelerators' parameter tables (`accelbench list accels --markdown`).
#
#   scripts/docs-params.sh [--check] [ACCELBENCH]
#
# Each page holds an accelerator's table between the marker comments
#   <!-- params:NAME begin --> ... <!-- params:NAME end -->
# and the default mode rewrites those sections in place. --check rewrites
# nothing: it prints a diff for every section that differs from the
# generated text, and names every accelerator no page (or more than one
# page) holds, and exits 1 if there was any. ACCELBENCH defaults to
# $ACCELBENCH, then build/harness/accelbench.
set -u
here=$(cd "$(dirname "$0")/.." && pwd)
check=0
if [ "${1:-}" = --check ]; then check=1; shift; fi
ab=${1:-${ACCELBENCH:-$here/build/harness/accelbench}}
gen=$("$ab" list accels --markdown) || { echo "docs-params.sh: '$ab list accels --markdown' failed" >&2; exit 2; }
# $(...) drops the output's last newline, which the last section's end marker needs.
GEN="$gen"$'\n' exec python3 - "$here/docs/accels" "$check" "$ab" <<'PY'
import difflib, glob, os, re, sys

docs, check, ab = sys.argv[1], sys.argv[2] == "1", sys.argv[3]
sect = re.compile(r"<!-- params:([A-Za-z0-9_.-]+) begin -->\n.*?<!-- params:\1 end -->\n", re.S)
generated = {m.group(1): m.group(0) for m in sect.finditer(os.environ["GEN"])}
pages = {p: open(p).read() for p in sorted(glob.glob(os.path.join(docs, "*.md")))}
where = {name: [p for p, text in pages.items() if f"<!-- params:{name} begin -->" in text] for name in generated}
problems = 0
for name, ps in where.items():
    if len(ps) != 1:
        problems += 1
        print(f"{name}: its parameter section is on {len(ps)} pages of {docs} ({', '.join(ps) or 'none'}); "
              f"it must be on exactly one, between <!-- params:{name} begin --> and <!-- params:{name} end -->")
for p, text in pages.items():
    for m in sect.finditer(text):
        name = m.group(1)
        if name not in generated:
            problems += 1
            print(f"{p}: a parameter section for '{name}', which `accelbench list accels` does not list")
            continue
        if m.group(0) != generated[name] and check:
            problems += 1
            sys.stdout.writelines(difflib.unified_diff(m.group(0).splitlines(True), generated[name].splitlines(True),
                                                       f"{p} (params:{name})", f"{ab} list accels --markdown"))
    if not check:
        new = sect.sub(lambda m: generated.get(m.group(1), m.group(0)), text)
        if new != text:
            open(p, "w").write(new)
            print(f"rewrote {p}")
if check and problems:
    if any(len(ps) != 1 for ps in where.values()):
        print("an accelerator needs its page: put its two marker comments on one page of docs/accels/, then")
    print("regenerate the sections with: scripts/docs-params.sh " + ab)
    sys.exit(1)
if not check and any(len(ps) != 1 for ps in where.values()):
    sys.exit(1)
PY
