#!/usr/bin/python3
"""Keeps the documentation and the code telling the same story. Seven checks:

(a) citations: every `physics.md §X` in src/ app/ tests/ bench/ tools/ docs/ and README.md,
    and every unqualified `§X` there, names a section heading X of docs/physics.md. In this
    repository an unqualified § always means docs/physics.md (its preamble says so); a § right
    after another source's name (`Bartels et al. §3`, `UK03 §…`, `style.md §…`) is that
    source's and is not checked. Ranges (`§7.2–7.3`) check every section they span;
    chains (`§5.4, §6`) keep the owner of their first member.
(b) scene keys: the key tables of docs/config.md (first header cell 'key', under a heading that
    names its section, `[solver]`) are generated from src/cdpowder/config/scene_keys.hpp: each
    lies in a block `<!-- generated: scene keys [solver] -->` … `<!-- end generated -->` of its
    heading's section (the test scene_key_docs_check compares the blocks with the table; the
    C++ table is not read here), and no reader in src/cdpowder/config/ reads a scene key by a
    literal name (in.number("solver.dt", …)): keys are declared once, in scene_keys.hpp.
(c) test labels: every label of the docs/testing.md label table and of the ctest presets'
    label filters (CMakePresets.json) is carried by some test of tests/CMakeLists.txt, and
    every label a test carries is in the table.
(d) layers: the folder table of docs/architecture.md ("## Folders of the library") lists the
    library's folders from the bottom of the stack up; a file of src/cdpowder/<folder>/
    includes only headers of its own folder and of the folders listed before it (a header at
    the top of src/cdpowder, such as the generated version.hpp, is outside the layers; the lane
    code a file names in `#define CDP_LANE_CODE` counts as an include of it), and
    every folder of src/cdpowder is in the table. A stage in a folder of solver/ (solver/nlgs/)
    includes of solver/ only its own folder and solver/settings.hpp: the step calls the
    stages, never the other way round.
(e) machine paths: no text file under results/, docs/ or examples/ records a file by the
    absolute path of the machine that wrote it (`/…/examples/paper/scene.toml`): provenance
    names a file as the user named it, or relative to the repository; and nothing under
    results/ names a scratch file of /tmp (a gate's binaries are named by commit and sha256).
(f) citation: CITATION.cff's `version:` is the project's (CMakeLists.txt) and LICENSE exists.
(h) results: results/index.csv names every folder of results/ (and of results/paper/, as
    paper/NAME) once, with its sweep file (which
    exists), the commit of its results.csv header, and a status: record, superseded,
    exploratory or gates.
(g) stages: the section "## One time step" of docs/architecture.md has a subsection "### N. …"
    per member of the Stage enum of src/cdpowder/solver/step.hpp, in its order, and every
    function it names in backticks (`solve_nlgs()`, `solve_nlgs(contacts, …)`,
    `ActionCache::store()`) and every source file it names (`solver/nlgs/nlgs.cpp`) exists in
    src/cdpowder (or, `bench/…`, in the repository): a renamed or removed piece of a stage
    shows up here.

Debian python3, standard library only. Exit status 0 when all hold, 1 with one line per
problem otherwise. `--self-test` runs the checks on small synthetic trees, each broken in one
way, and fails unless each break is reported (and the unbroken tree passes).
"""
import argparse
import csv
import json
import pathlib
import re
import subprocess
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]

# ---------------------------------------------------------------------------------------------
# (a) citations of docs/physics.md

CITATION_SCOPE = ["src", "app", "tests", "bench", "tools", "docs", "README.md"]
TEXT_SUFFIXES = {".cpp", ".hpp", ".h", ".in", ".py", ".sh", ".md", ".txt", ".toml", ".cmake",
                 ".json", ".csv"}
SECTION = r"\d+(?:\.\d+)*"
CITATION = re.compile(r"§\s?(" + SECTION + r")(?:\s?[–-]\s?(" + SECTION + r"))?")
HEADING = re.compile(r"^#{1,6}\s+(?:§\s?)?(" + SECTION + r")\.?(?:\s|$)")
# a § right after one of these belongs to that source, not to physics.md
FOREIGN_OWNER = re.compile(
    r"(?:Bartels et al\.?|BUKWK\]?|UK03\]?|SUK09\]?|S\+12\]?|UKW05\]?|paper(?:'s)?|"
    r"style guide|(?<!physics)\.md|Sect\.|section)[\s,]*$", re.IGNORECASE)
PHYSICS_OWNER = re.compile(r"physics\.md[`\])]*[\s,]*(?:\([^)]*\)\s*)?$")
CHAIN = re.compile(r"^[\s,;/]*(?:and|or|&|,)?[\s,]*$")


def physics_sections(physics_md):
    """Section numbers of the headings of docs/physics.md, outside code fences."""
    sections = set()
    fenced = False
    for line in physics_md.splitlines():
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        match = None if fenced else HEADING.match(line)
        if match:
            sections.add(match.group(1))
    return sections


def expand_range(first, last):
    """§7.2–7.3 → 7.2, 7.3; §5.3–5.5 → 5.3, 5.4, 5.5; otherwise the two ends."""
    a, b = first.split("."), last.split(".")
    if len(a) == len(b) and a[:-1] == b[:-1] and int(a[-1]) <= int(b[-1]):
        return [".".join(a[:-1] + [str(k)]) for k in range(int(a[-1]), int(b[-1]) + 1)]
    return [first, last]


def citations_in_line(line):
    """The physics.md sections cited in one line (unqualified or after physics.md)."""
    cited = []
    previous_end = None
    previous_owner = None
    for match in CITATION.finditer(line):
        before = line[:match.start()]
        between = line[previous_end:match.start()] if previous_end is not None else None
        if between is not None and CHAIN.match(between):
            owner = previous_owner
        elif PHYSICS_OWNER.search(before):
            owner = "physics"
        elif FOREIGN_OWNER.search(before[-40:]):
            owner = "foreign"
        else:
            owner = "physics"  # an unqualified § is physics.md's (docs/physics.md preamble)
        if owner == "physics":
            if match.group(2):
                cited.extend(expand_range(match.group(1), match.group(2)))
            else:
                cited.append(match.group(1))
        previous_end, previous_owner = match.end(), owner
    return cited


def scoped_files(root):
    for entry in CITATION_SCOPE:
        path = root / entry
        if path.is_file():
            yield path
        elif path.is_dir():
            for f in sorted(path.rglob("*")):
                if f.is_file() and (f.suffix in TEXT_SUFFIXES or f.name == "CMakeLists.txt"):
                    yield f


def check_citations(root):
    problems = []
    physics = root / "docs" / "physics.md"
    if not physics.is_file():
        return [f"{physics.relative_to(root)}: missing; the code cites its sections"]
    sections = physics_sections(physics.read_text(encoding="utf-8"))
    if not sections:
        return ["docs/physics.md: no numbered section headings found (expected '## 5. …', "
                "'### 5.4 …')"]
    cited_any = 0
    for f in scoped_files(root):
        if f.resolve() == pathlib.Path(__file__).resolve():
            continue  # this file's § are the self-test's synthetic citations
        try:
            text = f.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            continue  # binary fixtures
        for number, line in enumerate(text.splitlines(), 1):
            if "§" not in line:
                continue
            for section in citations_in_line(line):
                cited_any += 1
                if section not in sections:
                    problems.append(
                        f"{f.relative_to(root)}:{number}: cites physics.md §{section}, but "
                        f"docs/physics.md has no heading '{section}' ({nearby(section, sections)})")
    if cited_any == 0:
        problems.append("no physics.md citation found at all: the citation parser is broken")
    return problems


def section_key(section):
    return [int(part) for part in section.split(".")]


def nearby(section, sections):
    """The headings next to a missing one, for the message."""
    parent = section.rsplit(".", 1)[0] if "." in section else None
    siblings = [s for s in sections if parent is not None and s.rsplit(".", 1)[0] == parent
                and "." in s]
    if siblings:
        return f"§{parent} has §{', §'.join(sorted(siblings, key=section_key))}"
    tops = sorted((s for s in sections if "." not in s), key=section_key)
    return f"its sections are §{', §'.join(tops)}"


# ---------------------------------------------------------------------------------------------
# (b) scene keys

READ_METHODS = r"(?:number|integer|boolean|choice|optional_number|vector3|required_string|string)"
DIRECT_READ = re.compile(r"\bin\." + READ_METHODS + r"\(\s*\"([a-z0-9_]+\.[a-z0-9_.]+)\"")
TABLE_HEADING = re.compile(r"^#{1,6}\s.*?`\[([a-z0-9_.]+)\]`")
BLOCK_START = re.compile(r"^<!-- generated: scene keys \[([a-z0-9_.]+)\] -->$")
BLOCK_END = "<!-- end generated -->"


def key_table_problems(config_md):
    """Key tables outside a generated block, blocks under another section's heading, blocks not
    closed; and the number of blocks."""
    problems = []
    section = None
    block = None  # (section, line) of the open block
    blocks = 0
    previous = ""
    for number, line in enumerate(config_md.splitlines(), 1):
        if block is None and re.match(r"^#{1,6}\s", line):
            match = TABLE_HEADING.match(line)
            section = match.group(1) if match else None
        start = BLOCK_START.match(line)
        if start and block is None:
            blocks += 1
            block = (start.group(1), number)
            if start.group(1) != section:
                problems.append(f"docs/config.md:{number}: the generated key table of "
                                f"`[{start.group(1)}]` is under the heading of "
                                f"{'`[' + section + ']`' if section else 'no section'}")
        elif line == BLOCK_END:
            block = None
        elif (block is None and line.startswith("|") and not previous.startswith("|")
              and line.strip().strip("|").split("|")[0].strip().lower() == "key"):
            problems.append(f"docs/config.md:{number}: a hand-written key table; the key tables "
                            "are generated from src/cdpowder/config/scene_keys.hpp: put "
                            f"'<!-- generated: scene keys [{section or '…'}] -->' and "
                            f"'{BLOCK_END}' in its place and run build/release/app/scene_key_docs "
                            "docs/config.md")
        previous = line
    if block is not None:
        problems.append(f"docs/config.md:{block[1]}: the generated block of `[{block[0]}]` is "
                        f"not closed by '{BLOCK_END}'")
    return problems, blocks


def check_scene_keys(root):
    config = root / "docs" / "config.md"
    problems, blocks = key_table_problems(config.read_text(encoding="utf-8"))
    if blocks == 0:
        problems.append("docs/config.md: no generated key table ('<!-- generated: scene keys "
                        "[system] -->'): the block parser is broken")
    for reader in sorted((root / "src" / "cdpowder" / "config").glob("*.cpp")):
        text = reader.read_text(encoding="utf-8")
        for match in DIRECT_READ.finditer(text):
            number = text.count("\n", 0, match.start()) + 1
            problems.append(f"{reader.relative_to(root)}:{number}: reads scene key "
                            f"'{match.group(1)}' by name; declare it in "
                            "src/cdpowder/config/scene_keys.hpp")
    return problems


# ---------------------------------------------------------------------------------------------
# (c) test labels

def carried_labels(tests_cmake):
    """Labels set on tests in tests/CMakeLists.txt (literal LABELS "a;b" only)."""
    labels = set()
    for value in re.findall(r"\bLABELS\s+\"([^\"]*)\"", tests_cmake):
        if "$" in value:
            continue  # the helper passing its argument on
        labels.update(v.strip() for v in value.split(";") if v.strip())
    return labels


def doc_labels(testing_md):
    """Labels of the first table under the '## Labels' heading of docs/testing.md (the one
    whose first column is headed 'label'; later tables of the section list tests)."""
    labels = {}
    in_section = False
    in_table = False
    for number, line in enumerate(testing_md.splitlines(), 1):
        if re.match(r"^#{1,6}\s", line):
            in_section = re.match(r"^#{1,6}\s+labels\b", line, re.IGNORECASE) is not None
            in_table = False
            continue
        if in_section and line.startswith("|") and not in_table and not labels:
            in_table = line.strip().strip("|").split("|")[0].strip().lower() == "label"
            continue
        if not line.startswith("|"):
            in_table = False
            continue
        if in_section and in_table:
            first = line.strip().strip("|").split("|")[0]
            for label in re.findall(r"`([A-Za-z0-9_-]+)`", first):
                labels.setdefault(label, number)
    return labels


def preset_labels(presets_json):
    """Labels named in the testPresets' include/exclude label filters (a regex: alternatives
    of plain names)."""
    labels = {}
    for preset in json.loads(presets_json).get("testPresets", []):
        for kind in ("include", "exclude"):
            value = preset.get("filter", {}).get(kind, {}).get("label")
            if value:
                for label in re.split(r"\|", value.strip("^$()")):
                    labels.setdefault(label.strip("^$() "), []).append(preset.get("name", "?"))
    return labels


def check_labels(root):
    problems = []
    carried = carried_labels((root / "tests" / "CMakeLists.txt").read_text(encoding="utf-8"))
    if not carried:
        return ["tests/CMakeLists.txt: no test labels found: the label parser is broken"]
    documented = doc_labels((root / "docs" / "testing.md").read_text(encoding="utf-8"))
    if not documented:
        problems.append("docs/testing.md: no label table under a '## Labels' heading")
    presets = root / "CMakePresets.json"
    in_presets = preset_labels(presets.read_text(encoding="utf-8")) if presets.is_file() else {}
    for label, line in sorted(documented.items()):
        if label not in carried:
            problems.append(f"docs/testing.md:{line}: label '{label}' is carried by no test in "
                            "tests/CMakeLists.txt")
    for label, names in sorted(in_presets.items()):
        if label not in carried:
            problems.append(f"CMakePresets.json: test presets {', '.join(names)} filter on label "
                            f"'{label}', which no test in tests/CMakeLists.txt carries")
    for label in sorted(carried - documented.keys()):
        problems.append(f"tests/CMakeLists.txt: label '{label}' is not in the label table of "
                        "docs/testing.md")
    return problems


# ---------------------------------------------------------------------------------------------
# (d) the library's layers

LAYER_ROW = re.compile(r"^\|\s*`([a-z_]+)/`\s*\|")
# an include, or the lane code a file compiles through core/lanes_instantiate.inc (the
# `#define CDP_LANE_CODE "cdpowder/<folder>/…"` before it): that code becomes the defining file's
LIBRARY_INCLUDE = re.compile(r'^\s*#\s*(?:include|define\s+CDP_LANE_CODE)\s+"cdpowder/([a-z_]+)/')


def layer_order(architecture_md):
    """The folders of the table under '## Folders of the library', in table order."""
    order = []
    in_section = False
    for line in architecture_md.splitlines():
        if line.startswith("## "):
            in_section = line.strip() == "## Folders of the library"
            continue
        match = LAYER_ROW.match(line) if in_section else None
        if match:
            order.append(match.group(1))
    return order


def check_layers(root):
    architecture = root / "docs" / "architecture.md"
    library = root / "src" / "cdpowder"
    if not library.is_dir():
        return []
    order = layer_order(architecture.read_text(encoding="utf-8")) if architecture.is_file() else []
    if not order:
        return ["docs/architecture.md: no folder table under '## Folders of the library'"]
    rank = {folder: i for i, folder in enumerate(order)}
    problems = []
    folders = sorted(p.name for p in library.iterdir() if p.is_dir())
    for folder in folders:
        if folder not in rank:
            problems.append(f"src/cdpowder/{folder}/: not in the folder table of "
                            "docs/architecture.md")
    for folder in order:
        if folder not in folders:
            problems.append(f"docs/architecture.md: the folder table names {folder}/, which "
                            "src/cdpowder does not have")
    for path in sorted(library.rglob("*")):
        if path.suffix not in {".cpp", ".hpp", ".inc"} or path.parent == library:
            continue
        folder = path.relative_to(library).parts[0]
        if folder not in rank:
            continue
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            match = LIBRARY_INCLUDE.match(line)
            if match and match.group(1) in rank and rank[match.group(1)] > rank[folder]:
                problems.append(f"{path.relative_to(root)}:{number}: {folder}/ includes "
                                f"{match.group(1)}/, a folder above it (docs/architecture.md, "
                                "'Folders of the library')")
            problems += stage_folder_problems(path.relative_to(library), line,
                                              f"{path.relative_to(root)}:{number}")
    return problems


SOLVER_INCLUDE = re.compile(r'^\s*#\s*(?:include|define\s+CDP_LANE_CODE)\s+"cdpowder/solver/([^"]+)"')


def stage_folder_problems(relative, line, where):
    """A stage in a folder of solver/ (solver/nlgs/) is called by the step, never calls it:
    of solver/ it includes its own folder and the settings alone."""
    parts = relative.parts
    if len(parts) < 3 or parts[0] != "solver":
        return []
    match = SOLVER_INCLUDE.match(line)
    if not match:
        return []
    target = match.group(1)
    if target == "settings.hpp" or target.startswith(parts[1] + "/"):
        return []
    return [f"{where}: solver/{parts[1]}/ includes solver/{target}; a stage's folder includes "
            "its own headers and solver/settings.hpp alone (docs/architecture.md, "
            "'Folders of the library')"]


# ---------------------------------------------------------------------------------------------
# (e) machine paths in recorded outputs

PATH_SCOPE = ["results", "docs", "examples"]
# an absolute path that reaches one of the repository's folders: /<one or more folders>/examples/…
# (not a URL's //host/…, not part of a longer word or relative path)
MACHINE_PATH = re.compile(r"(?<![\w.:/~-])/(?:[\w.+-]+/)+?"
                          r"(?:examples|results|src|tests|tools|bench|docs|app)/[\w.=,+-]")
# in a recorded result: a scratch file of the machine that ran it (a gate's binaries); the docs'
# commands may name /tmp as a place to write to
SCRATCH_PATH = re.compile(r"(?<![\w.:/~-])/tmp/[\w.+-]")


def tracked_files(root, tops):
    """The files under `tops` that git tracks (a run's ignored outputs are not the record);
    every file there when `root` is not a git checkout."""
    try:
        listed = subprocess.run(["git", "-C", str(root), "ls-files", "--", *tops], check=True,
                                capture_output=True, text=True).stdout.splitlines()
        return [root / name for name in listed]
    except (OSError, subprocess.CalledProcessError):
        return [p for top in tops for p in sorted((root / top).rglob("*"))]


def check_machine_paths(root):
    problems = []
    for path in tracked_files(root, PATH_SCOPE):
        if path.is_file() and path.suffix in TEXT_SUFFIXES | {".svg"}:
            for number, line in enumerate(path.read_text(encoding="utf-8",
                                                         errors="replace").splitlines(), 1):
                match = MACHINE_PATH.search(line)
                if not match and path.relative_to(root).parts[0] == "results":
                    match = SCRATCH_PATH.search(line)
                if match:
                    problems.append(f"{path.relative_to(root)}:{number}: records the machine "
                                    f"path '{match.group(0)}…'; name files relative to the "
                                    "repository or as the user named them")
                    break
    return problems


# ---------------------------------------------------------------------------------------------
# (h) the index of the results

RESULT_STATUSES = {"record", "superseded", "exploratory", "gates"}
TABLE_COMMIT = re.compile(r"^# cdpowder \S+ \(commit ([0-9a-f]+(?:-dirty)?)\)")


def check_results_index(root):
    results = root / "results"
    if not results.is_dir():
        return []
    index = results / "index.csv"
    if not index.is_file():
        return ["results/index.csv is missing: it names each folder's status (record, "
                "superseded, exploratory, gates)"]
    with open(index, encoding="utf-8", newline="") as f:
        rows = list(csv.DictReader(f))
    problems = []
    # a folder of results is a folder of results/, or one level down in results/paper/ (the
    # results of record: results/paper/table1, …)
    folders = sorted(p.name for p in results.iterdir() if p.is_dir() and p.name != "paper")
    if (results / "paper").is_dir():
        folders += sorted(f"paper/{p.name}" for p in (results / "paper").iterdir() if p.is_dir())
    listed = [row.get("folder", "") for row in rows]
    for folder in folders:
        if listed.count(folder) != 1:
            problems.append(f"results/index.csv: lists results/{folder}/ {listed.count(folder)} "
                            "times, expected once")
    for number, row in enumerate(rows, 2):
        where = f"results/index.csv:{number}"
        folder = row.get("folder", "")
        if folder not in folders:
            problems.append(f"{where}: results/{folder}/ does not exist")
            continue
        if row.get("status") not in RESULT_STATUSES:
            problems.append(f"{where}: status '{row.get('status')}', expected one of "
                            f"{', '.join(sorted(RESULT_STATUSES))}")
        sweep = row.get("sweep file", "")
        if sweep and not (root / sweep).is_file():
            problems.append(f"{where}: the sweep file {sweep} does not exist")
        table = results / folder / "results.csv"
        if table.is_file():
            with open(table, encoding="utf-8") as f:
                match = TABLE_COMMIT.match(f.readline())
            if match and match.group(1) != row.get("program commit", ""):
                problems.append(f"{where}: program commit '{row.get('program commit')}', but "
                                f"results/{folder}/results.csv names {match.group(1)}")
    return problems


# ---------------------------------------------------------------------------------------------
# (f) the citation file

def check_citation(root):
    citation, cmake = root / "CITATION.cff", root / "CMakeLists.txt"
    if not citation.is_file() or not cmake.is_file():
        return []
    problems = [] if (root / "LICENSE").is_file() else ["LICENSE: missing (CITATION.cff names one)"]
    cited = re.search(r"^version:\s*([\w.]+)", citation.read_text(encoding="utf-8"), re.MULTILINE)
    project = re.search(r"project\(cdpowder VERSION ([\w.]+)", cmake.read_text(encoding="utf-8"))
    if project and (cited is None or cited.group(1) != project.group(1)):
        problems.append(f"CITATION.cff: version {cited.group(1) if cited else '(none)'} is not "
                        f"the project's {project.group(1)} (CMakeLists.txt)")
    return problems


def step_section(architecture_md):
    """The text of "## One time step", up to the next "## " heading ("" when absent)."""
    m = re.search(r"^## One time step\n(.*?)(?=^## |\Z)", architecture_md, re.MULTILINE | re.DOTALL)
    return m.group(1) if m else ""


def stage_enum(step_hpp):
    """The members of `enum class Stage { … , Count }`, Count left out."""
    m = re.search(r"enum class Stage\s*\{([^}]*)\}", step_hpp)
    names = [n.strip() for n in m.group(1).split(",")] if m else []
    return [n for n in names if n and n != "Count"]


def check_stages(root):
    architecture = root / "docs" / "architecture.md"
    step_hpp = root / "src" / "cdpowder" / "solver" / "step.hpp"
    if not architecture.is_file() or not step_hpp.is_file():
        return []
    section = step_section(architecture.read_text(encoding="utf-8"))
    where = "docs/architecture.md, One time step"
    if not section:
        return ["docs/architecture.md: no section '## One time step'"]
    problems = []
    headings = re.findall(r"^### (\d+)\. ", section, re.MULTILINE)
    stages = stage_enum(step_hpp.read_text(encoding="utf-8"))
    if [int(h) for h in headings] != list(range(1, len(stages) + 1)):
        problems.append(f"{where}: subsections {', '.join(headings) or 'none'} for the "
                        f"{len(stages)} stages of solver/step.hpp ({', '.join(stages)}); "
                        "expected '### 1.' to " f"'### {len(stages)}.'")
    sources = "\n".join(p.read_text(encoding="utf-8", errors="replace")
                        for p in sorted((root / "src" / "cdpowder").rglob("*"))
                        if p.is_file() and p.suffix in (".hpp", ".cpp", ".inc"))
    for name in sorted(set(re.findall(r"`((?:\w+::)?\w+)\(", section))):
        last = name.split("::")[-1]
        if not re.search(rf"\b{last}\s*\(", sources):
            problems.append(f"{where}: `{name}()` is named, but src/cdpowder has no such function")
    for path in sorted(set(re.findall(r"`(\w+/\w+\.(?:cpp|hpp|inc))`", section))):
        if not (root / "src" / "cdpowder" / path).is_file() and not (root / path).is_file():
            problems.append(f"{where}: `{path}` is named, but neither src/cdpowder/{path} nor "
                            f"{path} exists")
    return problems


def run_checks(root):
    return (check_citations(root) + check_scene_keys(root) + check_labels(root) +
            check_layers(root) + check_machine_paths(root) + check_citation(root) +
            check_results_index(root) +
            check_stages(root))


# ---------------------------------------------------------------------------------------------
# self-test on synthetic trees

GOOD_TREE = {
    "docs/physics.md": "# Spec\n\n## 2. Units\n\n## 5. Local problem\n\n### 5.3 Cache\n\n"
                       "### 5.4 Laws\n\n### 5.5 Code\n\n```\n## 9 not a heading\n```\n",
    "src/a.hpp": "// a.hpp — the laws (physics.md §5.4, §2); cache (§5.3–5.5).\n"
                 "// paper value (Bartels et al. §3); style guide 3.7\n",
    "docs/model.md": "Units (physics.md §2). See [physics.md §5](physics.md).\n",
    "README.md": "nothing cited\n",
    "src/cdpowder/config/scene_reader.cpp":
        'x = in.number(key.dotted(), x, key.range);\n'
        'if (in.has(detail::kDepositionTable)) {}\n',
    "docs/config.md": "# Scene\n\n## `[solver]` — time step\n\n"
                      "<!-- generated: scene keys [solver] -->\n\n| key | default |\n"
                      "| --- | --- |\n| `dt` | 0.01 |\n\n<!-- end generated -->\n\n"
                      "## `[contact]` — laws\n\n<!-- generated: scene keys [contact] -->\n"
                      "| key | default |\n| --- | --- |\n| `mu` | 0.3 |\n<!-- end generated -->\n\n"
                      "## `[particles]`\n\n| column | meaning |\n"
                      "| --- | --- |\n| `x`, `y` | centre |\n",
    "tests/CMakeLists.txt": 'cdpowder_add_test(a SOURCE a.cpp LABELS "unit;physics")\n'
                            'function(f name)\n  g(${name} LABELS "${ARG_LABELS}")\nendfunction()\n'
                            'set_tests_properties(t PROPERTIES LABELS "slow")\n',
    "docs/testing.md": "# Testing\n\n## Labels\n\n| label | what |\n| --- | --- |\n"
                       "| `unit` | x |\n| `physics`, `slow` | y |\n\n## Habits\n\n| `other` | z |\n",
    "docs/architecture.md": "# Architecture\n\n## Folders of the library\n\n"
                            "| folder | responsibility |\n| --- | --- |\n| `core/` | x |\n"
                            "| `solver/` | y |\n| `config/` | z |\n\n## One time step\n\n| `io/` | not a layer |\n"
                            "### 1. Detect\n\n`detect(world, …)`, `solver/step.cpp`.\n\n"
                            "### 2. Solve\n\n`Cache::store()`.\n\n## Next\n\n`gone()`\n",
    "src/cdpowder/solver/step.hpp": "enum class Stage { Detect, Solve, Count };\n"
                                    "void detect(int world);\nstruct Cache { void store(); };\n",
    "src/cdpowder/core/vec3.hpp": "#include <vector>\n",
    "src/cdpowder/solver/step.cpp": '#include "cdpowder/core/vec3.hpp"\n'
                                    '#include "cdpowder/solver/step.hpp"\n'
                                    '#include "cdpowder/version.hpp"\n',
    "CMakePresets.json": json.dumps({"testPresets": [
        {"name": "release", "filter": {"exclude": {"label": "slow"}}},
        {"name": "slow", "filter": {"include": {"label": "slow"}}}]}),
}


def write_tree(base, tree):
    for name, text in tree.items():
        path = base / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")


class SelfTest(unittest.TestCase):
    def problems(self, **changes):
        tree = dict(GOOD_TREE)
        for name, edit in changes.items():
            name = name.replace("__", "/").replace("_DOT_", ".")
            tree[name] = edit(tree.get(name, ""))
        with tempfile.TemporaryDirectory() as tmp:
            write_tree(pathlib.Path(tmp), tree)
            return run_checks(pathlib.Path(tmp))

    def assert_reported(self, problems, *fragments):
        text = "\n".join(problems)
        for fragment in fragments:
            self.assertIn(fragment, text, f"not reported: {fragment!r}; got:\n{text}")

    def test_a_results_folder_missing_from_the_index(self):
        problems = self.problems(
            results__a__results_DOT_csv=lambda t: "# cdpowder 0.1.0 (commit abc123)\nx\n",
            results__b__results_DOT_csv=lambda t: "# cdpowder 0.1.0 (commit def456)\nx\n",
            results__index_DOT_csv=lambda t: ("folder,sweep file,program commit,status,note\n"
                                               "a,,abc999,record,\n"))
        self.assert_reported(problems, "lists results/b/ 0 times",
                             "program commit 'abc999', but results/a/results.csv names abc123")

    def test_a_record_in_results_paper(self):
        problems = self.problems(
            results__paper__table1__results_DOT_csv=lambda t: "# cdpowder 0.1.0 (commit abc123)\nx\n",
            results__index_DOT_csv=lambda t: ("folder,sweep file,program commit,status,note\n"
                                               "paper/fig5,,abc123,record,\n"))
        self.assert_reported(problems, "lists results/paper/table1/ 0 times",
                             "results/paper/fig5/ does not exist")

    def test_a_scratch_path_in_a_gate_record(self):
        problems = self.problems(results__gates__x_DOT_md=lambda t: "- base: `/tmp/cdp_head`\n")
        self.assert_reported(problems, "results/gates/x.md:1: records the machine path '/tmp/c")

    def test_a_machine_path_in_a_result(self):
        text = ("# scene: /home/me/repo/examples/q/scene.toml\n"
                "# url: http://www.w3.org/2000/svg\n")
        p = self.problems(**{"results/t/results.csv": lambda _: text})
        self.assert_reported(p, "results/t/results.csv:1: records the machine path")
        self.assertEqual(len([x for x in p if "machine path" in x]), 1)

    def test_a_citation_of_another_version(self):
        p = self.problems(**{"CITATION.cff": lambda _: "cff-version: 1.2.0\nversion: 0.0.9\n",
                             "CMakeLists.txt": lambda _: "project(cdpowder VERSION 0.1.0 LANGUAGES CXX)\n",
                             "LICENSE": lambda _: "MIT\n"})
        self.assert_reported(p, "CITATION.cff: version 0.0.9 is not the project's 0.1.0")
        self.assertEqual(len(p), 1)

    def test_good_tree_passes(self):
        self.assertEqual(self.problems(), [])

    def test_citation_of_a_missing_section(self):
        p = self.problems(src__b_DOT_cpp=lambda _: "// see physics.md §7.6\n")
        self.assert_reported(p, "src/b.cpp:1: cites physics.md §7.6")

    def test_unqualified_citation_and_chain(self):
        p = self.problems(tests__t_DOT_cpp=lambda _: "// the laws (§5.4, §12.11)\n")
        self.assert_reported(p, "tests/t.cpp:1: cites physics.md §12.11")
        self.assertEqual(len(p), 1)

    def test_range_checks_every_section(self):
        p = self.problems(src__c_DOT_hpp=lambda _: "// physics.md §5.3–5.6\n")
        self.assert_reported(p, "cites physics.md §5.6", "§5 has §5.3, §5.4, §5.5")
        self.assertEqual(len(p), 1)

    def test_other_sources_are_not_physics(self):
        self.assertEqual(citations_in_line("(Bartels et al. §3; physics.md §8)"), ["8"])
        self.assertEqual(citations_in_line("paper §4; see physics.md §5.4"), ["5.4"])
        self.assertEqual(citations_in_line("(Bartels et al. §2, §3)"), [])
        self.assertEqual(citations_in_line("physics.md §15 items 3–5"), ["15"])
        self.assertEqual(citations_in_line("(§3, §7.6)"), ["3", "7.6"])

    def test_heading_removed_from_physics_md(self):
        p = self.problems(docs__physics_DOT_md=lambda t: t.replace("### 5.4 Laws\n", ""))
        self.assert_reported(p, "src/a.hpp:1: cites physics.md §5.4", "cites physics.md §5.4")

    def test_hand_written_key_table(self):
        p = self.problems(docs__config_DOT_md=lambda t: t.replace(
            "<!-- generated: scene keys [contact] -->\n", "").replace(
            "<!-- end generated -->\n\n## `[particles]`", "\n## `[particles]`"))
        self.assert_reported(p, "docs/config.md:15: a hand-written key table")
        self.assertEqual(len(p), 1)

    def test_generated_block_under_another_heading(self):
        p = self.problems(docs__config_DOT_md=lambda t: t.replace(
            "scene keys [contact]", "scene keys [contact.wall]"))
        self.assert_reported(p, "the generated key table of `[contact.wall]` is under the "
                             "heading of `[contact]`")
        self.assertEqual(len(p), 1)

    def test_generated_block_not_closed(self):
        p = self.problems(docs__config_DOT_md=lambda t: t.replace(
            "| `mu` | 0.3 |\n<!-- end generated -->", "| `mu` | 0.3 |"))
        self.assert_reported(p, "the generated block of `[contact]` is not closed")

    def test_key_read_by_name(self):
        p = self.problems(src__cdpowder__config__scene_reader_DOT_cpp=lambda t: t +
                          'z = in.boolean(\n    "solver.warm_start", z);\n')
        self.assert_reported(p, "scene_reader.cpp:3: reads scene key 'solver.warm_start' by name")
        self.assertEqual(len(p), 1)

    def test_label_in_docs_carried_by_no_test(self):
        p = self.problems(docs__testing_DOT_md=lambda t: t.replace("| `unit` | x |",
                                                                   "| `unit`, `gpu` | x |"))
        self.assert_reported(p, "label 'gpu' is carried by no test")

    def test_label_of_a_preset_carried_by_no_test(self):
        p = self.problems(CMakePresets_DOT_json=lambda t: t.replace('"include": {"label": "slow"}',
                                                                    '"include": {"label": "slo"}'))
        self.assert_reported(p, "test presets slow filter on label 'slo'")

    def test_label_on_a_test_missing_from_docs(self):
        p = self.problems(tests__CMakeLists_DOT_txt=lambda t: t +
                          'set_tests_properties(u PROPERTIES LABELS "unit;bench")\n')
        self.assert_reported(p, "label 'bench' is not in the label table")

    def test_labels_outside_the_label_section_do_not_count(self):
        self.assertNotIn("other", doc_labels(GOOD_TREE["docs/testing.md"]))


    def test_include_pointing_up_the_stack(self):
        problems = self.problems(src__cdpowder__core__vec3_DOT_hpp=lambda t: t + '#include "cdpowder/solver/settings.hpp"\n')
        self.assert_reported(problems, "src/cdpowder/core/vec3.hpp:2: core/ includes solver/")

    def test_lane_code_pointing_up_the_stack(self):
        problems = self.problems(src__cdpowder__core__vec3_DOT_hpp=lambda t: t + '#define CDP_LANE_CODE "cdpowder/solver/kernel.inc"\n')
        self.assert_reported(problems, "src/cdpowder/core/vec3.hpp:2: core/ includes solver/")

    def test_stage_folder_including_the_step(self):
        problems = self.problems(src__cdpowder__solver__nlgs__pass_DOT_hpp=lambda t: (
            '#include "cdpowder/solver/settings.hpp"\n#include "cdpowder/solver/nlgs/x.hpp"\n'
            '#include "cdpowder/solver/step.hpp"\n'))
        self.assert_reported(problems, "src/cdpowder/solver/nlgs/pass.hpp:3: solver/nlgs/ "
                             "includes solver/step.hpp")
        self.assertEqual(len([p for p in problems if "nlgs/pass.hpp" in p]), 1)

    def test_folder_missing_from_the_layers(self):
        problems = self.problems(src__cdpowder__io__vtk_DOT_cpp=lambda t: '#include "cdpowder/core/vec3.hpp"\n')
        self.assert_reported(problems, "src/cdpowder/io/: not in the folder table")

    def test_layer_row_of_a_folder_that_is_gone(self):
        problems = self.problems(docs__architecture_DOT_md=lambda t: t.replace(
            "| `config/` | z |\n", "| `config/` | z |\n| `gone/` | w |\n"))
        self.assert_reported(problems, "names gone/, which src/cdpowder does not have")

    def test_a_stage_without_its_section(self):
        problems = self.problems(src__cdpowder__solver__step_DOT_hpp=lambda t: t.replace(
            "Solve, Count", "Solve, Analyse, Count"))
        self.assert_reported(problems, "subsections 1, 2 for the 3 stages of solver/step.hpp")

    def test_a_stage_naming_a_function_that_is_gone(self):
        problems = self.problems(docs__architecture_DOT_md=lambda t: t.replace(
            "`Cache::store()`", "`Cache::store()`, `run_sweep()`, `solver/gone.cpp`"))
        self.assert_reported(problems, "`run_sweep()` is named, but src/cdpowder has no such",
                             "`solver/gone.cpp` is named, but neither src/cdpowder/solver/gone.cpp")

    def test_layers_without_a_folder_table(self):
        problems = self.problems(docs__architecture_DOT_md=lambda t: "# Architecture\n")
        self.assert_reported(problems, "docs/architecture.md: no folder table")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--root", type=pathlib.Path, default=ROOT, help="repository root")
    parser.add_argument("--self-test", action="store_true",
                        help="run the checks on synthetic broken trees instead")
    args = parser.parse_args()
    if args.self_test:
        suite = unittest.defaultTestLoader.loadTestsFromTestCase(SelfTest)
        result = unittest.TextTestRunner(verbosity=1).run(suite)
        return 0 if result.wasSuccessful() else 1
    problems = run_checks(args.root.resolve())
    for problem in problems:
        print(problem)
    sys.stdout.flush()
    if problems:
        print(f"check_docs: {len(problems)} problem(s); docs/physics.md, docs/config.md, "
              "docs/testing.md and docs/architecture.md must match the code "
              "(tests/docs/check_docs.py)")
        return 1
    print("check_docs: citations, scene keys, test labels, layers and the step's stages agree "
          "with the docs; no machine paths recorded")
    return 0


if __name__ == "__main__":
    sys.exit(main())
