#!/usr/bin/python3
"""Helpers for tools/probe/probe.sh (standard library only).

fmt.py head FILE N      first N characters of FILE, newlines -> ' | ', tabs -> ' ', control chars escaped
fmt.py errline FILE N   first line containing 'error' (or 'fault'/'interrupt'), cut to N characters
fmt.py maxline FILE     length in characters of the longest line
fmt.py ctrl FILE        number of lines holding control characters (other than tab, CR)
fmt.py porosity FILE    porosity and initial_porosity of a summary.json ('-' if absent)
fmt.py json FILE KEY.PATH   a value of a JSON file
fmt.py summary RESULTS  counts per category and verdict, then every case whose verdict is not
                        ok; exit status 1 if a case is crash, lost or unclear, else 0
"""
import json
import sys


def read(path):
    try:
        with open(path, "rb") as f:
            return f.read().decode("utf-8", errors="replace")
    except OSError:
        return ""


def clean(s):
    out = []
    for ch in s:
        o = ord(ch)
        if ch == "\t":
            out.append(" ")
        elif o < 32 or o == 127:
            out.append("\\x%02x" % o)
        else:
            out.append(ch)
    return "".join(out)


VERDICTS = ["ok", "unclear", "lost", "crash", "skipped"]
FAILING = {"unclear", "lost", "crash"}


def summary(path):
    """Prints the summary of a results.tsv; returns the exit status (1 if a case failed)."""
    lines = read(path).rstrip("\n").split("\n")
    header, rows = lines[0].split("\t"), [l.split("\t") for l in lines[1:] if l]
    col = {name: i for i, name in enumerate(header)}
    cats, counts = [], {}
    for r in rows:
        cat, v = r[col["category"]], r[col["verdict"]]
        if cat not in cats:
            cats.append(cat)
        counts[(cat, v)] = counts.get((cat, v), 0) + 1
    verdicts = VERDICTS + sorted({v for _, v in counts} - set(VERDICTS))
    table = [["category"] + verdicts + ["total"]]
    for cat in cats + ["all"]:
        n = [sum(c for (k, w), c in counts.items() if w == v and cat in (k, "all"))
             for v in verdicts]
        table.append([cat] + [str(x) for x in n] + [str(sum(n))])
    widths = [max(len(r[i]) for r in table) for i in range(len(table[0]))]
    for r in table:
        print("  ".join(c.ljust(w) if i == 0 else c.rjust(w)
                        for i, (c, w) in enumerate(zip(r, widths))))
    bad = [r for r in rows if r[col["verdict"]] != "ok"]
    print()
    print("%d case(s) not ok%s" % (len(bad), ":" if bad else ""))
    for r in bad:
        print("%s  %s  %s  exit %s" % (r[col["id"]], r[col["category"]], r[col["verdict"]],
                                       r[col["exit"]]))
        print("    command: %s" % r[col["command"]])
        if r[col["stderr_300"]]:
            print("    stderr:  %s" % r[col["stderr_300"]])
        print("    note:    %s" % r[col["note"]])
    return 1 if any(r[col["verdict"]] in FAILING for r in rows) else 0


def main():
    cmd, path = sys.argv[1], sys.argv[2]
    if cmd == "summary":
        sys.exit(summary(path))
    if cmd == "head":
        n = int(sys.argv[3])
        s = read(path).replace("\r\n", "\n").rstrip("\n")
        s = " | ".join(s.split("\n"))
        print(clean(s[:n]))
    elif cmd == "errline":
        n = int(sys.argv[3])
        for line in read(path).split("\n"):
            low = line.lower()
            if "error" in low or "fault" in low or "interrupt" in low or "warning" in low:
                print(clean(line[:n]))
                return
        lines = [l for l in read(path).split("\n") if l.strip() and not l.startswith("cdpowder ")]
        print(clean(lines[0][:n]) if lines else "")
    elif cmd == "maxline":
        print(max([len(l) for l in read(path).split("\n")] + [0]))
    elif cmd == "ctrl":
        n = 0
        for line in read(path).split("\n"):
            if any((ord(c) < 32 and c not in "\t\r") or ord(c) == 127 for c in line):
                n += 1
        print(n)
    elif cmd == "porosity":
        try:
            d = json.loads(read(path))
            p = d.get("porosity")
            print(p if p is not None else "-")
        except Exception as e:  # noqa: BLE001
            print("unreadable:%s" % type(e).__name__)
    elif cmd == "json":
        try:
            d = json.loads(read(path))
            for k in sys.argv[3].split("."):
                d = d[k]
            print(json.dumps(d))
        except Exception:  # noqa: BLE001
            print("-")


if __name__ == "__main__":
    main()
