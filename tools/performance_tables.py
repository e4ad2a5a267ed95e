#!/usr/bin/python3
"""Regenerates the tables of docs/performance.md from the CSV files under docs/performance/.

    tools/performance_tables.py [--root DIR]            rewrite the tables in place
    tools/performance_tables.py [--root DIR] --check    exit 1 (and print the command that
                                                         regenerates them) when one is stale
    tools/performance_tables.py --self-test             break synthetic trees, expect failures

Each table of docs/performance.md lies in a block

    <!-- generated: performance NAME -->
    …
    <!-- end generated -->

whose content is written from docs/performance/NAME.csv: the command as a shell block, the table,
and one line naming the machine, the commit, the date and what each number is. A CSV opens with
comment lines `# key: value` (a key given twice continues on a new line for `command`, with a
space otherwise), then a plain CSV table whose first row is the header:

    machine    the machine exactly: CPU model, cores, instruction set (required)
    commit     the engine's commit, or "per row" with a commit column (required)
    command    the command that measures it, one line each (required)
    date       when it was measured
    statistic  what one number of the table is ("The fastest of three alternated rounds")
    raw        the raw output the numbers come from
    note       for the reader of the CSV; not written to the page
    show       "table": the page shows the table and its line, not the command
    aggregate  min or median: rows of one group become one row, each numeric column the
               minimum or median of its values (the raw rounds stay in the CSV)
    group      the columns whose values make a group, separated by ";"
    columns    the columns the page shows and their order, separated by ";" (default: all)
    decimals   COLUMN=N;…: numbers of a column written with N decimals

Without `aggregate` each row is written as it is. A median of an even count is the mean of
the middle two, written with the inputs' most decimals. A CSV of docs/performance/ without
comment lines (whole_runs.csv, which tools/whole_run_bench.sh appends to) is not a table of
the page; one with them must be named by exactly one block.

Standard library only. Exit status 0 when the page is current (or was rewritten), 1 with
--check when a table is stale, 2 on a malformed page or CSV.
"""
import argparse
import csv
import io
import pathlib
import re
import sys
import tempfile
import unittest

DEFAULT_ROOT = pathlib.Path(__file__).resolve().parents[1]
PAGE = pathlib.Path("docs/performance.md")
CSV_DIR = pathlib.Path("docs/performance")
BLOCK_START = re.compile(r"^<!-- generated: performance ([A-Za-z0-9_.-]+) -->$")
BLOCK_END = "<!-- end generated -->"
REQUIRED = ("machine", "commit", "command")
KNOWN = REQUIRED + ("date", "statistic", "raw", "note", "show", "aggregate", "group",
                    "columns", "decimals")
NUMBER = re.compile(r"^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?$")


class TableError(Exception):
    """A page or CSV that regeneration cannot mend."""


def read_table_csv(path):
    """(metadata, header, rows) of a table CSV; metadata None when it has no comment lines."""
    text = path.read_text(encoding="utf-8")
    lines = text.splitlines()
    meta = {}
    body_start = 0
    for number, line in enumerate(lines):
        if not line.startswith("#"):
            body_start = number
            break
        body_start = number + 1
        m = re.match(r"^#\s*([a-z]+):\s?(.*)$", line)
        if not m or m.group(1) not in KNOWN:
            raise TableError(f"{path}:{number + 1}: expected '# key: value' with a key of "
                             f"{', '.join(KNOWN)}")
        key, value = m.group(1), m.group(2).rstrip()
        if key in meta:
            meta[key] += ("\n" if key == "command" else " ") + value
        else:
            meta[key] = value
    if body_start == 0:
        return None, [], []
    rows = [row for row in csv.reader(io.StringIO("\n".join(lines[body_start:]) + "\n"))
            if row]
    if not rows:
        raise TableError(f"{path}: no header row after the comment lines")
    header, rows = rows[0], rows[1:]
    for number, row in enumerate(rows, 2):
        if len(row) != len(header):
            raise TableError(f"{path}: table row {number} has {len(row)} cells, the header "
                             f"{len(header)}")
    for key in REQUIRED:
        if not meta.get(key, "").strip():
            raise TableError(f"{path}: the comment line '# {key}: …' is missing")
    return meta, header, rows


def split_list(value):
    return [item.strip() for item in value.split(";") if item.strip()]


def decimals_of(text):
    return len(text.split(".")[1]) if "." in text and "e" not in text.lower() else 0


def aggregate(values, how):
    """The minimum or median of number strings, as a string."""
    ordered = sorted(values, key=float)
    if how == "min":
        return ordered[0]
    middle = len(ordered) // 2
    if len(ordered) % 2:
        return ordered[middle]
    places = max(decimals_of(v) for v in values)
    return f"{(float(ordered[middle - 1]) + float(ordered[middle])) / 2:.{places}f}"


def table_rows(path, meta, header, rows):
    """The header and rows the page shows, after aggregation, selection and decimals."""
    how = meta.get("aggregate", "").strip()
    if how:
        if how not in ("min", "median"):
            raise TableError(f"{path}: aggregate is '{how}' (min or median)")
        group = split_list(meta.get("group", ""))
        for name in group:
            if name not in header:
                raise TableError(f"{path}: group names '{name}', not a column")
        keys, members = [], {}
        for row in rows:
            key = tuple(row[header.index(name)] for name in group)
            if key not in members:
                keys.append(key)
                members[key] = []
            members[key].append(row)
        merged = []
        for key in keys:
            out = []
            for index, name in enumerate(header):
                values = [row[index] for row in members[key]]
                if name in group or len(set(values)) == 1:
                    out.append(values[0])
                elif all(NUMBER.match(v.strip()) for v in values):
                    out.append(aggregate([v.strip() for v in values], how))
                else:
                    out.append(None)  # differs within the group: may not be shown
            merged.append(out)
        rows = merged
    shown = split_list(meta.get("columns", "")) or list(header)
    for name in shown:
        if name not in header:
            raise TableError(f"{path}: columns names '{name}', not a column")
    places = {}
    for item in split_list(meta.get("decimals", "")):
        name, _, count = item.rpartition("=")
        if name.strip() not in header or not count.strip().isdigit():
            raise TableError(f"{path}: decimals item '{item}' is not COLUMN=N")
        places[name.strip()] = int(count)
    out_rows = []
    for row in rows:
        out = []
        for name in shown:
            cell = row[header.index(name)]
            if cell is None:
                raise TableError(f"{path}: column '{name}' is not numeric and differs within "
                                 "a group; group by it or leave it out of columns")
            if name in places and NUMBER.match(cell.strip()):
                cell = f"{float(cell):.{places[name]}f}"
            out.append(cell)
        out_rows.append(out)
    return shown, out_rows


def markdown_row(cells):
    return "| " + " | ".join(c.strip().replace("|", "\\|") for c in cells) + " |"


def render_block(root, name):
    """The lines between a block's start and end markers for docs/performance/NAME.csv."""
    path = root / CSV_DIR / f"{name}.csv"
    if not path.is_file():
        raise TableError(f"{PAGE}: the block '{name}' has no {CSV_DIR / (name + '.csv')}")
    meta, header, rows = read_table_csv(path)
    if meta is None:
        raise TableError(f"{path}: no comment lines naming machine, commit and command")
    shown, out_rows = table_rows(path, meta, header, rows)
    show = meta.get("show", "").strip()
    if show not in ("", "table"):
        raise TableError(f"{path}: show is '{show}' (table, or no such line)")
    lines = [] if show == "table" else ["```sh", *meta["command"].split("\n"), "```"]
    lines += [markdown_row(shown), "| " + " | ".join("---" for _ in shown) + " |"]
    lines += [markdown_row(row) for row in out_rows]
    caption = f"Machine: {meta['machine'].rstrip('.')}. Commit {meta['commit']}"
    if meta.get("date"):
        caption += f", {meta['date']}"
    caption += "."
    if meta.get("statistic"):
        caption += f" {meta['statistic'].rstrip('.')}."
    caption += f" From `{(CSV_DIR / (name + '.csv')).as_posix()}`"
    if meta.get("raw"):
        caption += f"; raw output: {meta['raw'].rstrip('.')}"
    lines += ["", caption + "."]
    return lines


def regenerate(root, page_text):
    """(the page with every block rewritten, the names of the stale blocks)."""
    out, stale, named = [], [], []
    lines = page_text.split("\n")
    i = 0
    while i < len(lines):
        m = BLOCK_START.match(lines[i])
        if not m:
            if lines[i] == BLOCK_END:
                raise TableError(f"{PAGE}:{i + 1}: '{BLOCK_END}' without a block start")
            out.append(lines[i])
            i += 1
            continue
        name = m.group(1)
        if name in named:
            raise TableError(f"{PAGE}:{i + 1}: a second block of '{name}'")
        named.append(name)
        end = i + 1
        while end < len(lines) and lines[end] != BLOCK_END:
            if BLOCK_START.match(lines[end]):
                raise TableError(f"{PAGE}:{i + 1}: the block '{name}' is not closed")
            end += 1
        if end == len(lines):
            raise TableError(f"{PAGE}:{i + 1}: the block '{name}' is not closed by "
                             f"'{BLOCK_END}'")
        body = render_block(root, name)
        if lines[i + 1:end] != body:
            stale.append(name)
        out += [lines[i], *body, BLOCK_END]
        i = end + 1
    for path in sorted((root / CSV_DIR).glob("*.csv")):
        meta, _, _ = read_table_csv(path)
        if meta is not None and path.stem not in named:
            raise TableError(f"{path.relative_to(root)}: a table CSV that no block of {PAGE} "
                             f"names (add '<!-- generated: performance {path.stem} -->')")
    return "\n".join(out), stale


def regenerate_command(root):
    command = "tools/performance_tables.py"
    if root.resolve() != DEFAULT_ROOT:
        command += f" --root {root}"
    return command


def run(root, check, stdout=sys.stdout, stderr=sys.stderr):
    page = root / PAGE
    try:
        text = page.read_text(encoding="utf-8")
        new_text, stale = regenerate(root, text)
    except (OSError, TableError, csv.Error) as error:
        print(f"performance_tables: {error}", file=stderr)
        return 2
    if check:
        if stale or new_text != text:
            print(f"{PAGE}: the generated tables are stale ({', '.join(stale) or 'layout'}); "
                  f"regenerate them with: {regenerate_command(root)}", file=stdout)
            return 1
        return 0
    if new_text != text:
        page.write_text(new_text, encoding="utf-8")
        print(f"{PAGE}: rewrote {', '.join(stale)}", file=stdout)
    return 0


# ---------------------------------------------------------------------------------------------
# self-test: small trees, each broken in one way

GOOD_CSV = """# machine: Test CPU (family 1, model 2), 2 cores, AVX2
# commit: abc1234
# command: bench --filter=x
# command:     --more
# date: 2026-01-01
# statistic: The fastest of three rounds
# aggregate: min
# group: benchmark
# decimals: ns=1
benchmark,ns
a,3.04
a,2.96
b,7
"""

PAGE_TEXT = """# Page

<!-- generated: performance kernel -->
<!-- end generated -->

Tail.
"""


class SelfTest(unittest.TestCase):
    def tree(self, csv_text=GOOD_CSV, page_text=PAGE_TEXT, name="kernel"):
        directory = tempfile.TemporaryDirectory()
        self.addCleanup(directory.cleanup)
        root = pathlib.Path(directory.name)
        (root / CSV_DIR).mkdir(parents=True)
        (root / CSV_DIR / f"{name}.csv").write_text(csv_text, encoding="utf-8")
        (root / CSV_DIR / "whole_runs.csv").write_text("date,wall\n2026-01-01,3\n",
                                                       encoding="utf-8")
        (root / PAGE).write_text(page_text, encoding="utf-8")
        return root

    def status(self, root, check):
        out, err = io.StringIO(), io.StringIO()
        return run(root, check, out, err), out.getvalue() + err.getvalue()

    def test_a_fresh_block_is_stale_then_written_then_current(self):
        root = self.tree()
        code, message = self.status(root, check=True)
        self.assertEqual(code, 1)
        self.assertIn("tools/performance_tables.py --root", message)
        self.assertEqual(self.status(root, check=False)[0], 0)
        self.assertEqual(self.status(root, check=True)[0], 0)
        page = (root / PAGE).read_text(encoding="utf-8")
        self.assertIn("| a | 3.0 |", page)  # the minimum, one decimal
        self.assertIn("| b | 7.0 |", page)
        self.assertIn("<!-- generated: performance kernel -->\n```sh\nbench --filter=x\n"
                      "    --more\n```\n| benchmark | ns |", page)
        self.assertIn("Machine: Test CPU (family 1, model 2), 2 cores, AVX2. Commit abc1234, "
                      "2026-01-01. The fastest of three rounds.", page)
        self.assertIn("From `docs/performance/kernel.csv`.\n<!-- end generated -->\n\nTail.\n",
                      page)

    def test_show_table_leaves_the_command_out(self):
        root = self.tree(GOOD_CSV.replace("# date:", "# show: table\n# date:"))
        self.status(root, check=False)
        page = (root / PAGE).read_text(encoding="utf-8")
        self.assertIn("<!-- generated: performance kernel -->\n| benchmark | ns |", page)
        self.assertNotIn("```", page)

    def test_a_changed_measurement_makes_the_page_stale(self):
        root = self.tree()
        self.status(root, check=False)
        path = root / CSV_DIR / "kernel.csv"
        path.write_text(path.read_text(encoding="utf-8").replace("2.96", "2.50"),
                        encoding="utf-8")
        code, message = self.status(root, check=True)
        self.assertEqual(code, 1)
        self.assertIn("(kernel)", message)

    def test_a_hand_edit_inside_a_block_is_stale(self):
        root = self.tree()
        self.status(root, check=False)
        page = root / PAGE
        page.write_text(page.read_text(encoding="utf-8").replace("| a | 3.0 |", "| a | 2.0 |"),
                        encoding="utf-8")
        self.assertEqual(self.status(root, check=True)[0], 1)

    def test_the_median(self):
        self.assertEqual(aggregate(["3", "1", "2"], "median"), "2")
        self.assertEqual(aggregate(["1.0", "2.00", "4", "3"], "median"), "2.50")
        self.assertEqual(aggregate(["8.75", "9.1", "8.2"], "min"), "8.2")

    def test_a_missing_machine_is_an_error(self):
        root = self.tree(GOOD_CSV.replace("# machine: Test CPU (family 1, model 2), 2 cores, "
                                          "AVX2\n", ""))
        code, message = self.status(root, check=True)
        self.assertEqual(code, 2)
        self.assertIn("machine", message)

    def test_a_block_without_its_csv_is_an_error(self):
        root = self.tree(name="other")
        self.assertEqual(self.status(root, check=True)[0], 2)

    def test_a_table_csv_no_block_names_is_an_error(self):
        root = self.tree(page_text="# Page\n")
        code, message = self.status(root, check=True)
        self.assertEqual(code, 2)
        self.assertIn("no block", message)

    def test_an_unclosed_block_is_an_error(self):
        root = self.tree(page_text="<!-- generated: performance kernel -->\n| x |\n")
        self.assertEqual(self.status(root, check=True)[0], 2)

    def test_a_non_numeric_column_that_differs_in_a_group_is_an_error(self):
        root = self.tree(GOOD_CSV.replace("benchmark,ns\na,3.04\na,2.96",
                                          "benchmark,ns\na,3.04\na,n/a"))
        self.assertEqual(self.status(root, check=True)[0], 2)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--root", type=pathlib.Path, default=DEFAULT_ROOT,
                        help="the repository (default: the one this script is in)")
    parser.add_argument("--check", action="store_true",
                        help="change nothing; exit 1 when a table is stale")
    parser.add_argument("--self-test", action="store_true", help="run the self-test")
    args = parser.parse_args()
    if args.self_test:
        result = unittest.TextTestRunner(verbosity=1).run(
            unittest.defaultTestLoader.loadTestsFromTestCase(SelfTest))
        return 0 if result.wasSuccessful() else 1
    return run(args.root, args.check)


if __name__ == "__main__":
    sys.exit(main())
