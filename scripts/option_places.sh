#!/usr/bin/env bash
# Prints, for each fit option of FitOptionTable (core/fit/fit_options.cpp),
# the places its key or flag is written: its table entry; any other place in
# the code that handles fit options (core/fit/, the record's JSON, `sdcb fit`
# and `sdcb batch`, the usage text) that writes it out by hand, as a string
# literal "key", "flag" or "--flag" outside comments; and the lines of
# docs/CLI.md that show `--flag`. The goal is "1 table plus docs": nothing
# elsewhere. A literal of the same name that means something else (a round's
# "rmse_percent", the report's "basis_form") is counted apart, as listed in
# OTHER below.
#   scripts/option_places.sh           # one line per option, then a total
#   scripts/option_places.sh --where   # also each place outside the table
set -euo pipefail
cd "$(dirname "$0")/.."
python3 - "${1:-}" <<'PY'
import glob, re, sys
where = sys.argv[1] == "--where"
table_file = "core/fit/fit_options.cpp"
files = sorted(glob.glob("core/fit/*.h") + glob.glob("core/fit/*.cpp"))
files = [f for f in files if f != table_file] + [
    "io/report/fit_statistics_json.h", "io/report/fit_statistics_json.cpp",
    "tools/fit_command.cpp", "tools/batch_command.cpp", "tools/main.cpp"]
# Literals of an option's name that name something else: (file, literal).
OTHER = {
    ("io/report/fit_statistics_json.cpp", '"rmse_percent"'): "a round's error",
    ("io/report/fit_statistics_json.cpp", '"max_error_percent"'): "a round's error",
    ("tools/batch_command.cpp", '"rmse_percent"'): "the result's error",
    ("tools/batch_command.cpp", '"max_error_percent"'): "the result's error",
    ("io/report/fit_statistics_json.cpp", '"lambda"'): "the returned map's lambda",
    ("io/report/fit_statistics_json.cpp", '"basis_form"'): "the model's basis",
    ("tools/fit_command.cpp", '"knot_grid_bits"'): "the file's knot grid",
    ("tools/main.cpp", "--lambda"): "sdcb param's --lambda",
    ("tools/main.cpp", "--threads"): "another command's --threads",
    ("tools/main.cpp", "--max-control-points"): "the CAD export's",
}
src = open(table_file).read()
table = src[src.index("FitOptionTable() {"):]
entries = []
body = table[:table.index("\n  };")]
for entry in re.split(r"\n      Entry\(", body)[1:]:
    key = re.match(r'\s*"(\w+)",\s*&F::\w+', entry).group(1)
    flag = re.search(r'\.(?:Flag|Switch)\(\s*"([\w-]+)"', entry)
    entries.append((key, flag.group(1) if flag else None))

def literals(path):
    """(line number, string literal) of the code of `path`, comments out."""
    out, raw = [], False
    for n, line in enumerate(open(path).read().split("\n"), 1):
        # A line of a raw string R"(...)" (the usage text) is one literal.
        if raw or 'R"(' in line:
            raw = ')"' not in line
            out.append((n, '"' + line.split('R"(')[-1].split(')"')[0] + '"'))
            continue
        for m in re.finditer(r'"(?:[^"\\]|\\.)*"|//.*', line):
            if not m.group(0).startswith("//"):
                out.append((n, m.group(0)))
    return out

lits = {f: literals(f) for f in files}
docs = open("docs/CLI.md").read().split("\n")
print(f"{'option':26} {'flag':21} table elsewhere other docs/CLI.md")
total_else = total_other = 0
for key, flag in entries:
    rx = re.compile(r'^"%s"$' % re.escape(key) + (
        r'|^"%s"$|--%s\b' % (re.escape(flag), re.escape(flag)) if flag else ""))
    hits, other = [], []
    for f in files:
        for n, lit in lits[f]:
            if rx.search(lit):
                why = OTHER.get((f, lit)) or OTHER.get((f, "--" + (flag or "")))
                (other if why else hits).append((f, n, lit, why))
    doc = sum(1 for l in docs
              if flag and re.search(r'`--%s\b' % re.escape(flag), l))
    total_else += len(hits)
    total_other += len(other)
    shown = ("--" + flag) if flag else "-"
    print(f"{key:26} {shown:21} 1     {len(hits):<9} {len(other):<5} {doc}")
    if where:
        for f, n, lit, why in hits + other:
            print(f"    {f}:{n}: {lit}" + (f" ({why})" if why else ""))
print(f"{len(entries)} options: 1 table plus docs; {total_else} places "
      f"elsewhere; {total_other} literals of the same name meaning other things")
PY
