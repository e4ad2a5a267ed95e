#!/usr/bin/env bash
# tools/probe/probe.sh: an adversarial probe of the cdpowder command-line program.
#
# It gives the program bad inputs and hostile conditions and checks that each ends in a clear
# refusal, a clean fault or a valid run: never a crash, a hang or lost data. 285 cases in five
# categories, run one after the other; a full probe takes 2.5 to 5 min (2 min 21 s on a 2-core
# machine at load 3, 4 min 47 s in an earlier run):
#   scene  bad --set overrides, scene files, particles CSVs and sweep files
#   out    output folders: a file in the way, unwritable or immutable folders, a full disk (a
#          200 kB tmpfs), a file size limit, an older run, user files, a run still writing
#   num    numerical faults: huge or tiny pressures, time steps, radii, masses, densities
#   cli    the command line: missing, malformed and out-of-range options, damaged checkpoints
#   sig    SIGINT, SIGTERM, SIGHUP and SIGKILL to runs, resumes and sweeps, then a resume
#
# From the repository root:
#   tools/probe/probe.sh BUILD/app/cdpowder [OUTDIR]      # OUTDIR default /tmp/cdpowder-probe
#   ONLY=sig tools/probe/probe.sh build/release/app/cdpowder   # one category (names above)
#
# The binary is copied into OUTDIR/bin first, so a rebuild during the probe cannot mix builds;
# its --version and sha256 are in OUTDIR/probe_info.txt. Everything is written in OUTDIR,
# nothing in the repository: results.tsv (one line per case), summary.txt, the generated bad
# inputs (in/), each case's folder and its stdout/stderr (work/o/, work/logs/ID.out, ID.err).
# OUTDIR's bin/, in/ and work/ are replaced at each run, so OUTDIR must be new, empty or an
# earlier probe's (it holds the marker file .cdpowder-probe), and not inside the repository.
# OUTDIR and the repository path must not hold spaces or shell metacharacters: they are pasted
# into the cases' command lines, which results.tsv records as run.
# Needs bash, /usr/bin/python3 (standard library), coreutils, procps (pgrep), util-linux.
# Four cases need root: O008 and O009 (chattr +i), O024 (mount -t tmpfs), F053 (setpriv to
# user 65534); without root, the tool or a file system that allows it they are 'skipped'.
#
# results.tsv columns: id, category, command, exit, wall_s, stderr_300 (the first 300
# characters of stderr, newlines as ' | '), verdict, note (why; the first error line when it is
# not within the first 300 characters). Verdicts:
#   ok       the expected outcome: a bad input refused with a message holding what the case
#            asks for (the key, the value, what is allowed), a valid input run, a numerical
#            fault refused up front or stopped with exit 3 naming the quantity, sphere and step
#            (or a run to the end with a porosity in (0,1)), a signal honoured within 2.5 s
#            with a folder that resumes
#   unclear  refused or stopped, but the message or exit status does not say what is wrong
#            (words missing, a line over 400 characters, raw C++ exception text, control
#            characters, 'Success', a 60-digit number), exit 0 for a bad input, or a hang
#   lost     data lost: an existing file or older run changed by a refused or interrupted run,
#            user files removed, a run killed by another, processes left after a sweep ended
#   crash    killed by a signal (exit >= 128, unless the case sends it) or crash text on stderr
#            (terminate called, a sanitizer report, a segmentation fault)
#   skipped  not run here: needs root or a tool that is missing (the note says which)
# At the end the counts per category and verdict and every case not ok are printed and kept in
# OUTDIR/summary.txt. Exit status 0 when no case is crash, lost or unclear; 1 when one is;
# 2 for a usage error.
#
# PRE/POST are shell code in single quotes, run by eval; CHECK functions are called by name:
# shellcheck disable=SC2016,SC2317
set -u

die() { echo "probe.sh: $*" >&2; exit 2; }
usage() {
  echo "usage: [ONLY=scene|out|num|cli|sig] tools/probe/probe.sh CDPOWDER_BINARY [OUTDIR]" >&2
  echo "       OUTDIR defaults to /tmp/cdpowder-probe" >&2
  exit 2
}
if [ $# -lt 1 ] || [ $# -gt 2 ]; then usage; fi
ONLY=${ONLY:-all}
case "$ONLY" in all|scene|out|num|cli|sig) ;; *) die "ONLY=$ONLY: one of scene out num cli sig";; esac

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd -P) || die "cannot find the script's folder"
REPO=$(git -C "$HERE" rev-parse --show-toplevel 2>/dev/null) || REPO=$(cd "$HERE/../.." && pwd -P)
REPO=$(cd "$REPO" && pwd -P) || die "cannot enter the repository $REPO"
[ -f "$REPO/examples/quick/scene.toml" ] || die "$REPO does not look like the cdpowder repository"
for t in timeout awk pgrep md5sum sha256sum mkfifo truncate stat find xargs realpath; do
  command -v "$t" >/dev/null 2>&1 || die "needs $t"
done
[ -x /usr/bin/python3 ] || die "needs /usr/bin/python3"

case "$1" in /*) SRC_BIN=$1;; *) SRC_BIN=$PWD/$1;; esac
if [ ! -f "$SRC_BIN" ] || [ ! -x "$SRC_BIN" ]; then die "not an executable file: $1"; fi
OUTDIR=$(realpath -m -- "${2:-/tmp/cdpowder-probe}") || die "bad OUTDIR ${2:-}"
case "$OUTDIR/" in "$REPO"/*) die "OUTDIR $OUTDIR is inside the repository; give one outside it";; esac
for p in "$REPO" "$OUTDIR"; do
  case "$p" in *[!A-Za-z0-9._/+-]*) die "path with spaces or shell metacharacters: $p";; esac
done
# OUTDIR is cleared below: only an empty folder or one this script made (its marker file)
MARK=$OUTDIR/.cdpowder-probe
if [ -d "$OUTDIR" ] && [ -n "$(ls -A "$OUTDIR")" ] && [ ! -f "$MARK" ]; then
  die "$OUTDIR is not empty and was not made by this probe (no $MARK): give another OUTDIR"
fi

W=$OUTDIR/work
IN=$OUTDIR/in
BIN=$OUTDIR/bin/cdpowder
RES=$OUTDIR/results.tsv
Q=$REPO/examples/quick/scene.toml
PAPER=$REPO/examples/paper/scene.toml
L=$REPO/examples/lattice/scene.toml
LP=$REPO/examples/lattice/particles.csv
SIMP="--set run.until_blocked=false --set run.duration=1"
fmt() { /usr/bin/python3 "$HERE/fmt.py" "$@"; }

# leftovers of an earlier probe run (mounts, immutable folders); also at exit
undo_root_setups() {
  if mountpoint -q "$W/tiny" 2>/dev/null; then umount "$W/tiny"; fi
  if [ -d "$W" ] && command -v chattr >/dev/null 2>&1; then
    chattr -R -i "$W/imm" "$W/imm2" "$W/.trial_imm" 2>/dev/null
  fi
  return 0
}
undo_root_setups
trap undo_root_setups EXIT
rm -rf "$W" "$IN" "${OUTDIR:?}/bin" || die "cannot clear $W, $IN, $OUTDIR/bin"
mkdir -p "$OUTDIR/bin" "$W/logs" "$W/o" "$IN" || die "cannot create $OUTDIR"
echo "made by tools/probe/probe.sh; cleared by its next run" > "$MARK"
# The build may be replaced while the probe runs: every case uses one frozen copy of it.
{ cp -f "$SRC_BIN" "$BIN" && chmod 755 "$OUTDIR/bin" "$BIN"; } || die "cannot copy $SRC_BIN"
export PATH="$OUTDIR/bin:$PATH"
BIN_SHA=$(sha256sum < "$BIN" | cut -d' ' -f1)
{
  echo "binary: $SRC_BIN, copied to $BIN"
  echo "version: $("$BIN" --version 2>&1 | head -1)"
  echo "sha256: $BIN_SHA"
  echo "repository: $REPO at $(git -C "$REPO" rev-parse --short=12 HEAD 2>/dev/null || echo '(no git)')"
  echo "ONLY: $ONLY"
  echo "start: $(date -Is)"
} > "$OUTDIR/probe_info.txt"
/usr/bin/python3 "$HERE/gen_inputs.py" "$IN" "$REPO" "$BIN" || die "input generation failed"
cd "$W" || die "cannot enter $W"
set -m   # job control: background jobs keep the default SIGINT disposition

printf 'id\tcategory\tcommand\texit\twall_s\tstderr_300\tverdict\tnote\n' > "$RES"

now() { date +%s.%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN{printf "%.2f", b-a}'; }
cleancmd() { printf '%s' "$1" | tr '\t\n' '  ' | cut -c1-600; }

# record ID CAT CMD RC WALL ERRFILE VERDICT NOTE
record() {
  local id=$1 cat=$2 cmd=$3 rc=$4 wall=$5 err=$6 v=$7 note=$8
  local head; head=$(fmt head "$err" 300)
  local el; el=$(fmt errline "$err" 300)
  if [ -n "$el" ] && [[ "$head" != *"${el:0:120}"* ]]; then note="$note; error line: $el"; fi
  note=$(printf '%s' "$note" | sed 's/^; //' | tr '\t\n' '  ')
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$id" "$cat" "$(cleancmd "$cmd")" "$rc" "$wall" "$head" "$v" "$note" >> "$RES"
  printf '%-8s %-6s rc=%-4s %6ss %-8s %s\n' "$id" "$cat" "$rc" "$wall" "$v" "${note:0:150}"
}

# generic checks on the message; sets V/NOTE (only ever makes the verdict worse)
worse() {  # worse NEWVERDICT NOTE
  local rank_old rank_new
  case $V in ok) rank_old=0;; unclear) rank_old=1;; lost) rank_old=2;; crash) rank_old=3;; esac
  case $1 in ok) rank_new=0;; unclear) rank_new=1;; lost) rank_new=2;; crash) rank_new=3;; esac
  [ $rank_new -gt $rank_old ] && V=$1
  NOTE="$NOTE; $2"
}
generic_checks() {  # RC ERRFILE TIMEOUT
  local rc=$1 err=$2 to=$3
  if [ "$rc" -eq 124 ]; then worse unclear "timed out after ${to}s (hang)"; return; fi
  if [ "$rc" -ge 128 ]; then worse crash "killed by signal $((rc-128))"; fi
  if grep -a -q -E 'terminate called|AddressSanitizer|LeakSanitizer|UndefinedBehaviorSanitizer|runtime error:|Segmentation fault|Aborted|core dumped|stack smashing|double free|free\(\): ' "$err"; then
    worse crash "crash text in stderr"; fi
  local ml; ml=$(fmt maxline "$err")
  [ "$ml" -gt 400 ] && worse unclear "stderr line of $ml chars (>400)"
  grep -a -q 'Success' "$err" && worse unclear "'Success' in an error message"
  grep -a -q -E 'std::|what\(\)|bad_alloc|basic_string|vector::|stoi|stod' "$err" && worse unclear "raw C++ exception text, names no key/value"
  grep -a -q -E '[0-9]{60,}' "$err" && worse unclear "prints a number of $(grep -a -o -E '[0-9]{60,}' "$err" | head -1 | wc -c) digits"
  local nc; nc=$(fmt ctrl "$err")
  [ "$nc" -gt 0 ] && worse unclear "$nc stderr line(s) with control characters (garbage)"
}
needles_ok() {  # ERRFILE 'ERE1;ERE2;...' -> prints the missing ones
  local err=$1 IFS=';' n miss=""
  for n in $2; do [ -z "$n" ] && continue; grep -a -q -i -E -- "$n" "$err" || miss="$miss '$n'"; done
  printf '%s' "$miss"
}
summary_porosity() {  # DIR -> porosity or '-'
  if [ -f "$1/summary.json" ]; then fmt porosity "$1/summary.json"; else echo "-"; fi
}
porosity_valid() { awk -v p="$1" 'BEGIN{ if (p ~ /^[0-9.eE+-]+$/ && p+0 > 0 && p+0 < 1) exit 0; exit 1 }'; }

# run_case ID CAT EXPECT NEEDLES CMD [TIMEOUT]
#  EXPECT: reject (bad input: non-zero exit, message matching every NEEDLE)
#          either (exit 0 fine, or a refusal matching the needles)
#          accept (must run: exit 0 or 4)
#          fault  (refused with needles, or exit 3 with a fault naming quantity/body/step,
#                  or exit 0/4 with a porosity in (0,1))
#          help   (exit 0 with text on stdout)
#  PRE / POST: optional shell code (global variables) run before / after; POST may call worse.
#  OUT: the case's output folder (for fault/porosity checks); default o/ID
run_case() {
  local id=$1 cat=$2 exp=$3 needles=$4 cmd=$5 to=${6:-120}
  case "$ONLY" in all|"$cat") ;; *) PRE=; POST=; OUT=; return;; esac
  local err=$W/logs/$id.err out=$W/logs/$id.out
  local odir=${OUT:-o/$id}
  V=ok; NOTE=""
  [ -n "${PRE:-}" ] && eval "$PRE"
  local t0; t0=$(now)
  timeout -k 5 "$to" bash -c "$cmd" </dev/null >"$out" 2>"$err"; RC=$?
  local t1; t1=$(now); WALL=$(secs "$t0" "$t1")
  local rc=$RC
  generic_checks "$rc" "$err" "$to"
  if [ "$rc" -ne 124 ] && [ "$rc" -lt 128 ]; then
    local miss; miss=$(needles_ok "$err" "$needles")
    case $exp in
      reject)
        if [ "$rc" -eq 0 ]; then worse unclear "exit 0 for a bad input"
        elif [ -n "$miss" ]; then worse unclear "message lacks$miss"
        fi
        [ "$rc" -ne 0 ] && [ "$rc" -ne 2 ] && NOTE="$NOTE; exit $rc (docs: bad input -> 2)";;
      either)
        if [ "$rc" -eq 0 ]; then NOTE="$NOTE; accepted (exit 0)"
        elif [ -n "$miss" ]; then worse unclear "refused but message lacks$miss"
        else NOTE="$NOTE; refused (exit $rc)"; fi;;
      accept)
        if [ "$rc" -ne 0 ] && [ "$rc" -ne 4 ]; then worse unclear "valid input failed with exit $rc"; fi;;
      fault)
        if [ "$rc" -eq 0 ] || [ "$rc" -eq 4 ]; then
          local por; por=$(summary_porosity "$odir")
          local st; st=$(fmt json "$odir/summary.json" run.steps)
          if [ "$st" = 0 ]; then worse unclear "exit $rc after 0 steps: the run did nothing yet reports success (porosity $por)"
          elif porosity_valid "$por"; then NOTE="$NOTE; ran to the end (exit $rc, $st steps), porosity $por in (0,1)"
          else worse unclear "exit $rc with porosity '$por' (not in (0,1))"; fi
        elif [ "$rc" -eq 2 ]; then
          [ -n "$miss" ] && worse unclear "refused but message lacks$miss"
          NOTE="$NOTE; refused up front"
        elif [ "$rc" -eq 3 ]; then
          local fm; fm=$(needles_ok "$err" 'step [0-9]+;sphere [0-9]+|piston|wall')
          [ -n "$fm" ] && worse unclear "fault message lacks$fm"
          local fp; fp=$(fmt json "$odir/summary.json" run.failed)
          [ "$fp" != "true" ] && worse unclear "summary.json run.failed is '$fp'"
          NOTE="$NOTE; stopped by a fault (exit 3)"
        else worse unclear "exit $rc: neither refusal (2) nor fault (3)"; fi;;
      help)
        if [ "$rc" -ne 0 ] || [ ! -s "$out" ]; then worse unclear "help: exit $rc, stdout $(wc -c <"$out") bytes"; fi;;
    esac
  fi
  [ -n "${POST:-}" ] && eval "$POST"
  record "$id" "$cat" "$cmd" "$rc" "$WALL" "$err" "$V" "$NOTE"
  PRE=; POST=; OUT=
}

# Cases that need root. Each *_missing prints why such a case cannot run here ('' if it can).
root_missing() {  # root_missing TOOL...
  local t
  if [ "$(id -u)" -ne 0 ]; then printf 'needs root (running as uid %s)' "$(id -u)"; return; fi
  for t in "$@"; do
    command -v "$t" >/dev/null 2>&1 || { printf 'needs %s, which is not installed' "$t"; return; }
  done
}
chattr_missing() {  # chattr +i on a folder of $W (some file systems do not take it)
  local why; why=$(root_missing chattr)
  if [ -z "$why" ]; then
    mkdir -p "$W/.trial_imm"
    chattr +i "$W/.trial_imm" 2>/dev/null || why="chattr +i fails on the file system of $W"
    chattr -i "$W/.trial_imm" 2>/dev/null; rmdir "$W/.trial_imm" 2>/dev/null
  fi
  printf '%s' "$why"
}
tmpfs_missing() {  # mount -t tmpfs (a container may lack the capability)
  local why; why=$(root_missing mount umount mountpoint)
  if [ -z "$why" ]; then
    mkdir -p "$W/.trial_mnt"
    if mount -t tmpfs -o size=200k tmpfs "$W/.trial_mnt" 2>/dev/null; then umount "$W/.trial_mnt"
    else why="mount -t tmpfs fails here"; fi
    rmdir "$W/.trial_mnt" 2>/dev/null
  fi
  printf '%s' "$why"
}
setpriv_missing() {  # setpriv to user 65534
  local why; why=$(root_missing setpriv)
  if [ -z "$why" ] && ! setpriv --reuid=65534 --regid=65534 --clear-groups true 2>/dev/null; then
    why="setpriv --reuid=65534 fails here"
  fi
  printf '%s' "$why"
}
# skip_case ID CAT CMD NOTE: record a case that cannot run here (verdict 'skipped')
skip_case() {
  case "$ONLY" in all|"$2") ;; *) PRE=; POST=; OUT=; return;; esac
  : > "$W/logs/$1.err"
  record "$1" "$2" "$3" - 0.00 "$W/logs/$1.err" skipped "$4; not run"
  PRE=; POST=; OUT=
}
# run_if CHECK ID CAT EXPECT NEEDLES CMD [TIMEOUT]: run_case, or skip_case with the reason
# the function CHECK (one of the *_missing above) prints
run_if() {
  local check=$1 why; shift
  case "$ONLY" in all|"$2") ;; *) PRE=; POST=; OUT=; return;; esac
  why=$("$check")
  if [ -n "$why" ]; then skip_case "$1" "$2" "$5" "$why"; else run_case "$@"; fi
}

# snapshot of a folder's files (name + md5), for the 'lost' checks
# the names in folder $1, sorted, on one line
listing() { find "$1" -mindepth 1 -maxdepth 1 -printf '%f\n' 2>/dev/null | sort | tr '\n' ' '; }
snap() { (cd "$1" 2>/dev/null && find . -type f ! -name .run.lock -print0 | sort -z | xargs -0 -r md5sum) ; }
# an older, complete run in folder $1 (quick scene, 0.5 s)
older_run() { rm -rf "$1"; cdpowder compact "$Q" -o "$1" -q >/dev/null 2>&1; }

###########################################################################################
# 1. bad scene / --set / particles / sweep inputs
###########################################################################################
C="cdpowder compact $Q -q"
# --- --set: types, ranges, NaN/inf, huge values
run_case B001 scene reject 'contact\.mu;-1;≥ 0'            "$C -o o/B001 --set contact.mu=-1"
run_case B002 scene reject 'contact\.mu;nan;finite'         "$C -o o/B002 --set contact.mu=nan"
run_case B003 scene reject 'contact\.mu;inf;finite'         "$C -o o/B003 --set contact.mu=inf"
run_case B004 scene reject 'contact\.mu;abc;number'         "$C -o o/B004 --set 'contact.mu=\"abc\"'"
run_case B005 scene reject 'contact\.mu;malformed'          "$C -o o/B005 --set contact.mu"
run_case B006 scene reject 'contact\.mu;malformed|TOML|value' "$C -o o/B006 --set 'contact.mu='"
run_case B007 scene reject 'contact\.mu;malformed|TOML|value' "$C -o o/B007 --set 'contact.mu=0.3 extra'"
run_case B008 scene reject 'contact\.mu;malformed|TOML|value' "$C -o o/B008 --set 'contact.mu==1'"
run_case B009 scene reject 'deposition\.spheres;1000000000|1e9;integer' "$C -o o/B009 --set deposition.spheres=1e9"
run_case B010 scene reject 'deposition\.spheres;1000000000;10000000' "$C -o o/B010 --set deposition.spheres=1000000000"
run_case B011 scene reject 'deposition\.spheres;0;≥ 1'      "$C -o o/B011 --set deposition.spheres=0"
run_case B012 scene reject 'deposition\.spheres;-5;≥ 1|integer' "$C -o o/B012 --set deposition.spheres=-5"
run_case B013 scene reject 'deposition\.spheres;1\.5;integer' "$C -o o/B013 --set deposition.spheres=1.5"
run_case B014 scene reject 'deposition\.capture_radius;1e\+?10|10000000000;half the cell|at most' "$C -o o/B014 --set deposition.capture_radius=1e10"
run_case B015 scene reject 'solver\.dt;run\.duration|longer|at most'  "cdpowder simulate $Q -q -o o/B015 --set run.until_blocked=false --set run.duration=1 --set solver.dt=2"
run_case B016 scene reject 'system\.lx;-15|≥|> 0'            "$C -o o/B016 --set system.lx=-15"
run_case B017 scene reject 'system\.lx;0;> 0'                "$C -o o/B017 --set system.lx=0"
run_case B018 scene reject 'system\.lx|capture_radius;1e-09|5e-10'  "$C -o o/B018 --set system.lx=1e-9"
run_case B019 scene fault  'system\.lx;1e\+?09|1000000000'   "$C -o o/B019 --set system.lx=1e9"
run_case B020 scene fault  'system\.ly;1e\+?09|1000000000'   "$C -o o/B020 --set system.ly=1e9"
run_case B021 scene fault 'system\.lx;1e\+?300'             "$C -o o/B021 --set system.lx=1e300"
run_case B022 scene fault  'deposition\.radius;1e-300'       "$C -o o/B022 --set deposition.radius=1e-300"
run_case B023 scene reject 'deposition\.radius;-1;> 0'       "$C -o o/B023 --set deposition.radius=-1"
run_case B024 scene reject 'radius_min|radius_max;≤|min'     "$C -o o/B024 --set deposition.radius_min=1.2 --set deposition.radius_max=0.8 --set deposition.radius=1.0"
run_case B025 scene reject 'contact\.muu;unknown key;contact\.mu' "$C -o o/B025 --set contact.muu=1"
run_case B026 scene reject 'foo;unknown'                     "$C -o o/B026 --set foo=1"
run_case B027 scene reject 'malformed'                       "$C -o o/B027 --set =1"
run_case B028 scene reject 'contact..mu|contact\.\.mu|malformed|key' "$C -o o/B028 --set contact..mu=1"
run_case B029 scene reject 'system\.gravity;2;3'             "$C -o o/B029 --set 'system.gravity=[0,0]'"
run_case B030 scene reject 'system\.gravity;nan|finite'      "$C -o o/B030 --set 'system.gravity=[0,0,nan]'"
run_case B031 scene reject 'system\.gravity;down|array'      "$C -o o/B031 --set 'system.gravity=\"down\"'"
run_case B032 scene reject 'contact;table|section|unknown|expected' "$C -o o/B032 --set contact=1"
run_case B033 scene reject 'system\.lx\.foo|system\.lx;table|unknown|expected|number' "$C -o o/B033 --set system.lx.foo=1"
run_case B034 scene reject 'contact\.cohesion_rule;one of|graph'  "$C -o o/B034 --set 'contact.cohesion_rule=\"$(printf 'a%.0s' $(seq 1 2000))\"'"
run_case B035 scene reject 'contact\.k+;unknown'             "$C -o o/B035 --set \"contact.\$(head -c 100000 /dev/zero | tr '\\0' k)=1\""
run_case B036 scene reject 'solver\.seed;-1;≥ 0'             "$C -o o/B036 --set solver.seed=-1"
run_case B037 scene reject 'solver\.seed'                    "$C -o o/B037 --set solver.seed=18446744073709551616"
run_case B038 scene reject 'solver\.visit_order;Fixed;one of|fixed' "$C -o o/B038 --set 'solver.visit_order=\"Fixed\"'"
run_case B039 scene reject 'solver\.threads;65;64'           "$C -o o/B039 --set solver.threads=65"
run_case B040 scene reject 'solver\.threads|kernel;coloured'  "$C -o o/B040 --set solver.threads=2 --set 'solver.kernel=\"scalar\"'"
run_case B041 scene reject 'min_passes;max_passes'           "$C -o o/B041 --set solver.min_passes=500 --set solver.max_passes=10"
run_case B042 scene reject 'piston\.force|piston\.pressure;exactly one|together|not both' "$C -o o/B042 --set piston.force=1"
run_case B043 scene reject 'run\.until_blocked|compact;simulate|false' "$C -o o/B043 --set run.until_blocked=false"
run_case B044 scene reject 'run\.blocked\.window;1e\+?09|1000000000|steps' "$C -o o/B044 --set run.blocked.window=1e9"
run_case B045 scene reject 'run\.timeseries_every;0;≥ 1'     "$C -o o/B045 --set run.timeseries_every=0"
run_case B046 scene reject 'run\.snapshot_every;-1;≥ 0'      "$C -o o/B046 --set run.snapshot_every=-1"
run_case B047 scene reject 'system\.bottom_wall;yes|true'    "$C -o o/B047 --set 'system.bottom_wall=\"yes\"'"
POST='grep -a -q "from '"''"'" "$W/logs/B048.err" && NOTE="$NOTE; cosmetic: says R_max = 1 from '"''"' (an empty source name for a deposition)"'
run_case B048 scene reject 'system\.lx;2\.5|at least|≥'      "$C -o o/B048 --set system.lx=2.5 --set system.ly=2.5 --set deposition.capture_radius=1.2 --set 'deposition.capture_rule=\"surface_gap\"'"
run_case B049 scene reject 'capture_radius;radius_min|≥'     "$C -o o/B049 --set deposition.capture_radius=1.5"
run_case B050 scene reject 'piston\.height;≤ 0|> 0|-1'       "$C -o o/B050 --set piston.height=-1"
POST='grep -a -q "malformed override, expected section.key=value" "$W/logs/B051.err" && worse unclear "calls the well-formed override contact.µ=1 malformed (expected section.key=value); the real reason (µ is not a TOML bare key / not a scene key) is not given - the same key in a file (F041) gets unknown key; did you mean contact.mu"'
run_case B051 scene reject 'contact\.µ|unknown'              "$C -o o/B051 --set contact.µ=1"
run_case B052 scene reject 'piston\.enabled|compact|piston'  "$C -o o/B052 --set piston.enabled=false"
run_case B053 scene reject 'run\.max_duration;0|> 0'         "$C -o o/B053 --set run.max_duration=0"
run_case B054 scene reject 'solver\.tolerance;-1e-06|> 0'    "$C -o o/B054 --set solver.tolerance=-1e-6"
# --- scene files
CF="cdpowder compact -q"
POST='[ $RC -ne 0 ] && ! grep -a -q -i "bom\|byte.order\|feff\|efbbbf" "$W/logs/F001.err" && worse unclear "a BOM file is refused without saying the cause is the BOM"'
run_case F001 scene either 'bom.toml;BOM|byte order|UTF-8|syntax' "$CF -o o/F001 $IN/s/bom.toml"
run_case F002 scene reject 'empty.toml;deposition'   "$CF -o o/F002 $IN/s/empty.toml"
run_case F003 scene reject 'comments_only.toml;deposition'  "$CF -o o/F003 $IN/s/comments_only.toml"
run_case F004 scene reject 'nul_value.toml;NUL|null|control|syntax|character' "$CF -o o/F004 $IN/s/nul_value.toml"
run_case F005 scene reject 'nul_comment.toml;NUL|null|control|syntax|character' "$CF -o o/F005 $IN/s/nul_comment.toml"
run_case F006 scene reject 'nul_only.toml;NUL|null|control|syntax|character' "$CF -o o/F006 $IN/s/nul_only.toml"
run_case F007 scene reject 'elf.toml;syntax|UTF-8|character|TOML' "$CF -o o/F007 $IN/s/elf.toml"
run_case F008 scene reject 'longval.toml;contact\.cohesion_rule;one of' "$CF -o o/F008 $IN/s/longval.toml"
run_case F009 scene either 'longcomment.toml'                 "$CF -o o/F009 $IN/s/longcomment.toml"
run_case F010 scene reject 'longkey.toml;unknown key'          "$CF -o o/F010 $IN/s/longkey.toml"
run_case F011 scene either 'longnum.toml:[0-9]+;digits|length'           "$CF -o o/F011 $IN/s/longnum.toml"
run_case F012 scene reject 'unterminated_string.toml:[0-9]+;string|syntax' "$CF -o o/F012 $IN/s/unterminated_string.toml"
run_case F013 scene reject 'missing_value.toml:[0-9]+;syntax|value' "$CF -o o/F013 $IN/s/missing_value.toml"
run_case F014 scene reject 'dup_key.toml:[0-9]+;lx|redefin|duplicate' "$CF -o o/F014 $IN/s/dup_key.toml"
run_case F015 scene reject 'dup_table.toml:[0-9]+;system|redefin|duplicate' "$CF -o o/F015 $IN/s/dup_table.toml"
run_case F016 scene reject 'garbage_line.toml:[0-9]+;syntax|expected' "$CF -o o/F016 $IN/s/garbage_line.toml"
run_case F017 scene reject 'unterminated_header.toml:[0-9]+;syntax|expected|\]' "$CF -o o/F017 $IN/s/unterminated_header.toml"
run_case F018 scene reject 'unterminated_array.toml:[0-9]+;syntax|array|expected' "$CF -o o/F018 $IN/s/unterminated_array.toml"
run_case F019 scene reject 'bad_escape.toml:[0-9]+;escape|syntax' "$CF -o o/F019 $IN/s/bad_escape.toml"
run_case F020 scene reject 'deep_array.toml:[0-9]+;depth|nest' "$CF -o o/F020 $IN/s/deep_array.toml"
run_case F021 scene reject 'deep_table.toml:[0-9]+;depth|nest' "$CF -o o/F021 $IN/s/deep_table.toml"
run_case F022 scene reject 'int_overflow.toml:[0-9]+;spheres|integer|range|overflow' "$CF -o o/F022 $IN/s/int_overflow.toml"
run_case F023 scene reject 'float_overflow.toml:[0-9]+;1e400' "$CF -o o/F023 $IN/s/float_overflow.toml"
run_case F024 scene reject 'spheres_string.toml:[0-9]+;deposition\.spheres;integer' "$CF -o o/F024 $IN/s/spheres_string.toml"
run_case F025 scene reject 'spheres_bool.toml:[0-9]+;deposition\.spheres;integer' "$CF -o o/F025 $IN/s/spheres_bool.toml"
run_case F026 scene reject 'lx_date.toml:[0-9]+;system\.lx;number' "$CF -o o/F026 $IN/s/lx_date.toml"
run_case F027 scene reject 'lx_inf.toml:[0-9]+;system\.lx;finite' "$CF -o o/F027 $IN/s/lx_inf.toml"
run_case F028 scene reject 'typo_section.toml:[0-9]+;sytem;system' "$CF -o o/F028 $IN/s/typo_section.toml"
run_case F029 scene reject 'key_wrong_section.toml:[0-9]+;system\.mu;unknown' "$CF -o o/F029 $IN/s/key_wrong_section.toml"
run_case F030 scene reject 'section_as_value.toml:[0-9]+;system;table|section' "$CF -o o/F030 $IN/s/section_as_value.toml"
run_case F031 scene reject 'array_of_tables.toml:[0-9]+;system;table|section' "$CF -o o/F031 $IN/s/array_of_tables.toml"
run_case F032 scene accept ''                                  "$CF -o o/F032 $IN/s/crlf.toml"
run_case F033 scene either 'latin1.toml:[0-9]+;UTF-8|utf-8|encoding|character' "$CF -o o/F033 $IN/s/latin1.toml"
run_case F034 scene reject 'utf16.toml;UTF-8|UTF-16|encoding|character|syntax' "$CF -o o/F034 $IN/s/utf16.toml"
run_case F035 scene accept ''                                  "$CF -o o/F035 $IN/s/hex_int.toml"
run_case F036 scene reject 'both_dep_particles.toml;deposition;particles' "$CF -o o/F036 $IN/s/both_dep_particles.toml"
run_case F037 scene reject 'nope\.csv;cannot|not exist|No such|missing' "$CF -o o/F037 $IN/s/particles_missing.toml"
run_case F038 scene reject '/tmp;folder|directory|not a file' "$CF -o o/F038 $IN/s/particles_dir.toml"
run_case F039 scene reject 'no_spheres.toml;deposition' "$CF -o o/F039 $IN/s/no_spheres.toml"
POST='n=$(grep -c "^error" "$W/logs/F040.err"); [ "$n" -lt 4 ] && worse unclear "only $n of 4 mistakes reported (docs: all of them, one line each)"'
run_case F040 scene reject 'contact\.mu;contact\.mu_rol;contact\.cohesion_rule;system\.lx' "$CF -o o/F040 $IN/s/many_errors.toml"
run_case F041 scene reject 'µ;unknown'                         "$CF -o o/F041 $IN/s/unicode_key.toml"
# --- scene path itself
POST='grep -a -q -i "no such\|not exist\|missing" "$W/logs/F050.err" || NOTE="$NOTE; says cannot open, not why (no such file)"'
run_case F050 scene reject 'nope\.toml;cannot|No such|not exist' "cdpowder compact $W/nope.toml -o o/F050 -q"
run_case F051 scene reject '/tmp;folder|directory'            "cdpowder compact /tmp -o o/F051 -q"
PRE='rm -f "$W/fifo.toml"; mkfifo "$W/fifo.toml"'
run_case F052 scene reject 'fifo\.toml;regular|not a file|cannot' "cdpowder compact $W/fifo.toml -o o/F052 -q" 20
# (as user 65534: root reads a file of mode 000; the output goes to a folder that user may write)
PRE='cp "$Q" "$W/noread.toml"; chmod 000 "$W/noread.toml"; chmod o+x "$W" "$OUTDIR"; mkdir -p "$W/nobody"; chmod 1777 "$W/nobody"'
POST='grep -a -q -i "permission" "$W/logs/F053.err" || worse unclear "does not say permission denied"; rm -rf "$W/nobody/F053_out"'
run_if setpriv_missing F053 scene reject 'noread\.toml;cannot|Permission|permission' "setpriv --reuid=65534 --regid=65534 --clear-groups $BIN compact $W/noread.toml -o $W/nobody/F053_out -q"
run_case F054 scene reject 'scene|required|argument'          "cdpowder compact -o o/F054 -q"
POST='grep -a -q -i "empty\|'"''"'" "$W/logs/F055.err" || worse unclear "an empty scene name is shown as nothing (\"error: : cannot open\"), not said to be empty"'
run_case F055 scene reject "''|empty|cannot|scene"            "cdpowder compact '' -o o/F055 -q"
# --- particles CSV via --particles (lattice scene, simulate 1 t0)
S="cdpowder simulate $L -q $SIMP --particles"
run_case P001 scene reject 'missing\.csv;cannot|No such|not exist' "$S $IN/p/missing.csv -o o/P001"
run_case P002 scene reject "$IN/p;folder|directory"          "$S $IN/p -o o/P002"
run_case P003 scene reject 'empty\.csv;header|empty|no spheres|column'  "$S $IN/p/empty.csv -o o/P003"
run_case P004 scene reject 'header_only\.csv;no particles|header only' "$S $IN/p/header_only.csv -o o/P004"
run_case P005 scene reject 'no_r\.csv;\br\b|column'           "$S $IN/p/no_r.csv -o o/P005"
run_case P006 scene reject 'abc\.csv:[0-9]+;z;abc'            "$S $IN/p/abc.csv -o o/P006"
run_case P007 scene reject 'nan\.csv:[0-9]+;x;nan|finite'     "$S $IN/p/nan.csv -o o/P007"
run_case P008 scene reject 'inf_r\.csv:[0-9]+;r;inf|finite'   "$S $IN/p/inf_r.csv -o o/P008"
run_case P009 scene reject 'neg_r\.csv:[0-9]+;r;-1|> 0'       "$S $IN/p/neg_r.csv -o o/P009"
run_case P010 scene reject 'zero_r\.csv:[0-9]+;r;> 0'         "$S $IN/p/zero_r.csv -o o/P010"
run_case P011 scene fault  'same_centre\.csv;sphere'          "$S $IN/p/same_centre.csv -o o/P011"
run_case P012 scene fault  'overlap\.csv;sphere'              "$S $IN/p/overlap.csv -o o/P012"
POST='[ $RC -ne 0 ] && ! grep -a -q -i "bom\|byte.order\|feff" "$W/logs/P013.err" && worse unclear "BOM file refused without naming the BOM"'
run_case P013 scene either 'bom\.csv;BOM|byte order|column|header' "$S $IN/p/bom.csv -o o/P013"
run_case P014 scene accept ''                                  "$S $IN/p/crlf.csv -o o/P014"
run_case P015 scene reject 'huge_line\.csv:[0-9]+;column|field|value' "$S $IN/p/huge_line.csv -o o/P015"
run_case P016 scene fault 'huge_number\.csv'                  "$S $IN/p/huge_number.csv -o o/P016"
run_case P017 scene either 'unknown_col\.csv;colour'           "$S $IN/p/unknown_col.csv -o o/P017"
run_case P018 scene reject 'dup_col\.csv;x;twice|duplicate|repeated|again' "$S $IN/p/dup_col.csv -o o/P018"
run_case P019 scene reject 'short_row\.csv:[0-9]+;field|column|value' "$S $IN/p/short_row.csv -o o/P019"
run_case P020 scene reject 'long_row\.csv:[0-9]+;field|column|value' "$S $IN/p/long_row.csv -o o/P020"
run_case P021 scene reject 'fixed_maybe\.csv:[0-9]+;fixed;maybe' "$S $IN/p/fixed_maybe.csv -o o/P021"
run_case P022 scene fault 'outside_cell\.csv'                 "$S $IN/p/outside_cell.csv -o o/P022"
run_case P023 scene fault  'below_wall\.csv;sphere'            "$S $IN/p/below_wall.csv -o o/P023"
run_case P024 scene reject 'system\.lx|lx;at least|≥'          "$S $IN/p/big_r.csv -o o/P024"
run_case P025 scene reject 'nul\.csv:[0-9]+;z|NUL|character'   "$S $IN/p/nul.csv -o o/P025"
run_case P026 scene reject 'semicolon\.csv;column|header|x'    "$S $IN/p/semicolon.csv -o o/P026"
run_case P027 scene reject 'e400\.csv:[0-9]+;z;1e400|finite|range' "$S $IN/p/e400.csv -o o/P027"
run_case P028 scene reject 'binary\.csv;column|header'         "$S $IN/p/binary.csv -o o/P028"
POST='[ $RC -ne 0 ] && ! grep -a -q -i "empty\|trailing comma\|trailing or doubled comma\|no name\|'"''"'" "$W/logs/P029.err" && worse unclear "the empty column name (trailing comma) is not shown or named; the message suggests x"'
run_case P029 scene either 'trailing_comma\.csv;column|field'   "$S $IN/p/trailing_comma.csv -o o/P029"
run_case P030 scene either 'quoted\.csv;column|quote'           "$S $IN/p/quoted.csv -o o/P030"
run_case P031 scene reject 'missing_relative\.csv;cannot|No such|not exist' "cdpowder simulate $IN/p/scene_rel/scene.toml -q $SIMP -o o/P031"
run_case P032 scene reject 'deposit|particles|unknown|option' "cdpowder deposit $Q -o o/P032 --particles $LP"
run_case P033 scene reject 'particles|argument|value'          "cdpowder simulate $L -q $SIMP -o o/P033 --particles"
# --- sweep files (-j 1; the valid ones are 1 run of 0.5 s)
for f in set_malformed:'contact\.mu;malformed' set_unknown:'contact\.muu;unknown' set_not_array:'set;array|list|strings' \
         set_bad_value:'contact\.mu;-5;≥ 0' grid_out_of_range:'mu_roll;-1;≥ 0' grid_empty:'mu_roll;empty|non-empty' \
         grid_repeat:'mu_roll;repeat|twice|duplicate|more than once' grid_mixed:'mu_roll;a|number' grid_unknown_key:'mu_rol;unknown' \
         grid_nested:'mu_roll;list|array|number' grid_scalar:'mu_roll;list|array' grid_seed_key:'deposition\.seed;seed' \
         unknown_top:'seedz;unknown' seeds_zero:'seeds;0;1' seeds_dup:'seeds;1;distinct|twice|duplicate|repeat' \
         seeds_negative:'seeds;-1' seeds_too_many:'seeds;100001|100000' seeds_empty_list:'seeds;empty|non-empty|at least' \
         seeds_float:'seeds;1\.5|integer|count' seeds_neg_in_list:'seeds;-3|≥ 0|non-negative' scene_missing:'!nope_scene\.toml;cannot|No such|not exist' \
         no_scene:'scene;required|missing' scene_dir:'!/tmp;folder|directory' scene_not_string:'scene;string|5' \
         points_dup:'point;same|twice|duplicate' points_unknown:'mu_rol;unknown' seed_keys_unknown:'foo;unknown' \
         empty:'scene;required|missing|empty' bad_scene_content:'!typo_section\.toml;sytem' malformed:'malformed\.toml:[0-9]+;syntax|array|expected' \
         self_scene:'self_scene\.toml;scene|seeds|unknown'; do
  n=${f%%:*}; nd=${f#*:}
  i=$(printf 'W%03d' $(( ${SWI:-0} + 1 ))); SWI=$(( ${SWI:-0} + 1 ))
  if [ "${nd:0:1}" = '!' ]; then nd=${nd:1}; else nd="$n\.toml;$nd"; fi
  run_case "$i" scene reject "$nd" "cdpowder sweep $IN/sw/$n.toml -o o/$i -j 1 -q"
done
run_case W040 scene reject 'nope\.toml;cannot|No such|not exist' "cdpowder sweep $W/nope.toml -o o/W040 -q"
run_case W041 scene either 'seeds' "cdpowder sweep $IN/sw/seeds_float.toml -o o/W041 --dry-run" 60

###########################################################################################
# 2. output folder
###########################################################################################
C="cdpowder compact $Q -q"
PRE='echo data > "$W/afile"'
POST='[ "$(cat "$W/afile")" = data ] || worse lost "the existing file was changed"'
run_case O001 out reject "$W/afile;exist|folder|directory|not a folder" "$C -o $W/afile"
PRE='echo data > "$W/afile"'
run_case O002 out reject "$W/afile/sub;afile|not a folder|directory|Not a directory" "$C -o $W/afile/sub"
run_case O003 out reject '/proc/x;cannot|Permission|No such|read-only|create' "$C -o /proc/x"
run_case O004 out reject '/proc/x/y/z;cannot|Permission|No such|read-only|create' "$C -o /proc/x/y/z"
run_case O005 out reject "out|empty|''|folder" "$C -o ''"
run_case O006 out reject 'too long|File name|name' "$C -o o/$(printf 'n%.0s' $(seq 1 300))"
run_case O007 out reject 'too long|File name|name|path of [0-9]+ characters' "$C -o $W/o/$(for i in $(seq 1 40); do printf 'd%.0s' $(seq 1 120); printf /; done)x"
PRE='mkdir -p "$W/imm" && chattr -i "$W/imm" 2>/dev/null; rm -rf "$W/imm"; mkdir -p "$W/imm" && chattr +i "$W/imm"'
POST='chattr -i "$W/imm"'
run_if chattr_missing O008 out reject "imm;cannot|Permission|not permitted|write" "$C -o $W/imm"
PRE='mkdir -p "$W/imm2/run" && chattr -R -i "$W/imm2" 2>/dev/null; rm -rf "$W/imm2"; older_run "$W/imm2/run"; chattr +i "$W/imm2/run"; SNAP=$(snap "$W/imm2/run")'
POST='[ "$(snap "$W/imm2/run")" = "$SNAP" ] || worse lost "older run changed"; chattr -R -i "$W/imm2"'
run_if chattr_missing O009 out reject "imm2/run;cannot|Permission|not permitted|write" "$C -o $W/imm2/run"
# an existing folder with an older run: a valid new run replaces it (documented)
PRE='older_run "$W/o/O010"; touch -d "2000-01-01" "$W/o/O010"/*'
POST='n=$(find "$W/o/O010" -type f -mtime +3650 | wc -l); [ "$n" -gt 0 ] && worse lost "$n stale files of the older run remain beside the new ones"; grep -q "mu_roll = 0.5" "$W/o/O010/scene.toml" || worse unclear "new scene.toml not written"'
run_case O010 out accept '' "cdpowder compact $Q -q -o o/O010 --set contact.mu_roll=0.5"
# an older run + a bad input: must write nothing
PRE='older_run "$W/o/O011"; SNAP=$(snap "$W/o/O011")'
POST='[ "$(snap "$W/o/O011")" = "$SNAP" ] || worse lost "older run changed by a refused input"'
run_case O011 out reject 'contact\.mu;-1' "$C -o o/O011 --set contact.mu=-1"
# an older run + a new run that fails at once (fault): older outputs replaced by the failed run (documented?)
PRE='older_run "$W/o/O012"; SNAP=$(snap "$W/o/O012")'
POST='NOTE="$NOTE; older run replaced by the failed run: $(listing "$W/o/O012")"'
run_case O012 out fault 'solver\.dt' "$C -o o/O012 --set solver.dt=100"
# an older run + a new run whose deposition is interrupted (SIGINT after 1 s of a 1e6-sphere deposit)
PRE='older_run "$W/o/O013"; SNAP=$(snap "$W/o/O013")'
POST='if [ "$(snap "$W/o/O013")" != "$SNAP" ]; then worse lost "older complete run in the folder was destroyed by a new run that was interrupted before writing anything (now: $(listing "$W/o/O013"))"; else NOTE="$NOTE; older run kept intact"; fi'
run_case O013 out reject 'interrupt|stopped|signal' "bash -c 'set -m; cdpowder compact $PAPER -q -o o/O013 --set deposition.spheres=1000000 --set system.lx=800 --set system.ly=800 & p=\$!; sleep 1; kill -INT \$p; wait \$p'"
# user files in the folder must survive
PRE='mkdir -p "$W/o/O014"; echo mine > "$W/o/O014/notes.txt"; mkdir -p "$W/o/O014/mydata"; echo x > "$W/o/O014/mydata/a.csv"; echo keep > "$W/o/O014/particles_backup.csv"'
POST='for f in notes.txt mydata/a.csv particles_backup.csv; do [ -f "$W/o/O014/$f" ] || worse lost "user file $f removed"; done'
run_case O014 out accept '' "$C -o o/O014"
# --out the folder that holds the scene file itself
PRE='mkdir -p "$W/o/O015"; cp "$Q" "$W/o/O015/scene.toml"; SUM=$(md5sum < "$W/o/O015/scene.toml")'
POST='[ "$(md5sum < "$W/o/O015/scene.toml")" = "$SUM" ] || worse lost "the input scene file (with its comments) was silently overwritten by the output scene.toml"'
run_case O015 out either 'scene\.toml' "cdpowder compact $W/o/O015/scene.toml -q -o o/O015"
# --particles file inside the output folder
PRE='mkdir -p "$W/o/O016"; cp "$LP" "$W/o/O016/particles.csv"; SUM=$(md5sum < "$W/o/O016/particles.csv")'
POST='[ "$(md5sum < "$W/o/O016/particles.csv")" = "$SUM" ] || worse lost "the input --particles file was silently overwritten by the output particles.csv"'
run_case O016 out either 'particles\.csv' "cdpowder simulate $L -q $SIMP --particles $W/o/O016/particles.csv -o o/O016"
# --out . in a folder with user files
PRE='rm -rf "$W/dot"; mkdir -p "$W/dot"; echo mine > "$W/dot/notes.txt"; echo 1,2 > "$W/dot/contacts.csv"; SUM=$(md5sum < "$W/dot/contacts.csv")'
POST='[ -f "$W/dot/notes.txt" ] || worse lost "notes.txt removed"; NOTE="$NOTE; a user file named contacts.csv in the folder was $( [ "$(md5sum < "$W/dot/contacts.csv")" = "$SUM" ] && echo kept || echo replaced)"'
run_case O017 out either '' "cd $W/dot && cdpowder compact $Q -q -o ."
PRE='mkdir -p "$W/real17"; ln -sfn "$W/real17" "$W/o/O018"'
POST='[ -f "$W/real17/summary.json" ] || worse unclear "nothing written through the symlink"'
run_case O018 out accept '' "$C -o o/O018"
PRE='ln -sfn "$W/does/not/exist" "$W/o/O019"'
POST='grep -a -q -i "symlink\|symbolic\|dangling\|does/not/exist" "$W/logs/O019.err" || worse unclear "does not say that o/O019 is a dangling symlink (to $W/does/not/exist)"'
run_case O019 out either 'O019|does/not/exist' "$C -o o/O019"
run_case O020 out reject '/dev/null;folder|directory|exist' "$C -o /dev/null"
PRE='echo data > "$W/afile"'
run_case O021 out reject "$W/afile;folder|directory|exist" "cdpowder deposit $Q -o $W/afile"
PRE='echo data > "$W/afile"'
run_case O022 out reject "$W/afile;folder|directory|exist" "cdpowder sweep $IN/sw/valid1.toml -o $W/afile -q"
run_case O023 out accept '' "$C -o \$'o/new\\nline \\\\ \"q\" \\x01'"
# a full disk: a 200 kB tmpfs
PRE='mkdir -p "$W/tiny"; mountpoint -q "$W/tiny" || mount -t tmpfs -o size=200k tmpfs "$W/tiny"'
POST='umount "$W/tiny"'
run_if tmpfs_missing O024 out reject 'No space left|space' "$C -o $W/tiny/run"
# a file-size limit (SIGXFSZ unless ignored)
run_case O025 out reject 'File too large|too large|limit' "ulimit -f 64; exec $C -o o/O025"
# a second run into a folder a run is writing into
PRE='rm -rf "$W/o/O026"; (cdpowder compact "$PAPER" -q -o "$W/o/O026" --set deposition.spheres=60000 --set system.lx=200 --set system.ly=200 >/dev/null 2>&1 & echo $! > "$W/O026.pid"); sleep 1.5'
POST='p=$(cat "$W/O026.pid"); if kill -0 "$p" 2>/dev/null; then NOTE="$NOTE; first run still alive"; else worse lost "first run died"; fi; kill -TERM "$p"; for _ in $(seq 1 100); do kill -0 "$p" 2>/dev/null || break; sleep 0.1; done; g=$(fmt json "$W/o/O026/summary.json" run.interrupted); [ "$g" = true ] || worse lost "first run did not end with interrupted outputs (interrupted=$g)"'
run_case O026 out reject 'lock|in use|another|running|writ' "$C -o o/O026"
# resume into a folder holding an older finished run (no checkpoint)
PRE='older_run "$W/o/O027"; SNAP=$(snap "$W/o/O027")'
POST='[ "$(snap "$W/o/O027")" = "$SNAP" ] || worse lost "finished run changed by a refused resume"'
run_case O027 out reject 'checkpoint' "cdpowder resume o/O027"

###########################################################################################
# 4. numerical faults (quick scene compact, max_duration bounded)
###########################################################################################
C="cdpowder compact $Q -q --set run.max_duration=300"
run_case N001 num fault 'piston\.pressure;1e\+?06|1000000' "$C -o o/N001 --set piston.pressure=1e6"
run_case N002 num fault 'solver\.dt;100'           "$C -o o/N002 --set solver.dt=100"
run_case N003 num fault 'system\.gravity'          "$C -o o/N003 --set 'system.gravity=[0,0,-1e6]'"
run_case N004 num fault 'deposition\.radius'       "$C -o o/N004 --set deposition.radius=1e-300"
run_case N005 num fault 'deposition\.radius'       "$C -o o/N005 --set deposition.radius=1e-6 --set deposition.capture_radius=3e-6"
run_case N006 num fault 'piston\.mass'             "$C -o o/N006 --set piston.mass=1e-300"
run_case N007 num fault 'piston\.force'            "cdpowder compact $IN/s/force_huge.toml -q --set run.max_duration=300 -o o/N007"
run_case N008 num fault 'piston\.pressure'         "$C -o o/N008 --set piston.pressure=1e300"
run_case N009 num fault 'contact\.cohesion_force'  "$C -o o/N009 --set contact.cohesion_force=1e300"
run_case N010 num fault 'piston\.velocity'         "$C -o o/N010 --set piston.velocity=-1e6"
run_case N011 num fault 'system\.density'          "$C -o o/N011 --set system.density=1e-300"
run_case N012 num fault 'system\.density'          "$C -o o/N012 --set system.density=1e300"
run_case N013 num fault 'piston\.velocity'         "$C -o o/N013 --set piston.velocity=1e300"
run_case N014 num fault 'piston\.height'           "$C -o o/N014 --set piston.height=1e300"
run_case N015 num fault 'system\.gravity'          "$C -o o/N015 --set 'system.gravity=[1e308,0,0]'"
run_case N016 num fault 'contact\.mu'              "$C -o o/N016 --set contact.mu=1e300"
run_case N017 num fault 'run\.max_overlap'         "$C -o o/N017 --set run.max_overlap=1e-300"
run_case N018 num fault 'velocity|vx'              "cdpowder simulate $L -q $SIMP --particles $IN/p/huge_velocity.csv -o o/N018" 
OUT=o/N019
run_case N019 num fault 'solver\.dt'               "cdpowder simulate $Q -q -o o/N019 --set run.until_blocked=false --set run.duration=1 --set solver.dt=1e-300" 30
run_case N020 num fault 'piston\.mass;1e\+?300'    "$C -o o/N020 --set piston.mass=1e300"
run_case N021 num fault 'solver\.dt'               "cdpowder simulate $Q -q -o o/N021 --set run.until_blocked=false --set run.duration=10 --set solver.dt=5 --set piston.pressure=1"
run_case N022 num fault 'fixed'                    "cdpowder compact $L -q --set run.max_duration=300 --particles $IN/p/all_fixed.csv -o o/N022"
# out of memory (a 400 MB address space for a deposit of 5 million spheres): named, not
# "std::bad_alloc", with its own exit status (6)
run_case N023 num reject 'out of memory;depositing;5000000 spheres' "ulimit -v 400000; exec $C -o o/N023 --set deposition.spheres=5000000 --set system.lx=3000 --set system.ly=3000"

###########################################################################################
# 5. command line
###########################################################################################
run_case X001 cli reject 'subcommand|command|required' "cdpowder"
run_case X002 cli reject 'frob;simulate|compact|commands' "cdpowder frob"
run_case X003 cli help '' "cdpowder --help"
run_case X004 cli help '' "cdpowder --version"
run_case X005 cli help '' "cdpowder simulate --help"
run_case X006 cli help '' "cdpowder compact --help"
run_case X007 cli help '' "cdpowder deposit --help"
run_case X008 cli help '' "cdpowder resume --help"
run_case X009 cli help '' "cdpowder sweep --help"
i=10
for v in 0 -1 abc nan inf 1e400 "''" 1e-300 "' 5 '" 50x; do
  i=$((i+1))
  if [ "$v" = 1e-300 ]; then
    run_case X0$i cli either 'checkpoint-every;1e-300' "cdpowder simulate $Q -q -o o/X0$i --set run.until_blocked=false --set run.duration=1 --checkpoint-every $v" 30
  elif [ "$v" = "' 5 '" ]; then
    run_case X0$i cli either 'checkpoint-every' "cdpowder compact $Q -q -o o/X0$i --checkpoint-every $v"
  else
    run_case X0$i cli reject "checkpoint-every;> 0|time" "cdpowder compact $Q -q -o o/X0$i --checkpoint-every $v"
  fi
done
i=30
SQ="cdpowder sweep $IN/sw/valid1.toml -q -j 1"
for v in abc -5 0 5x 1h2h "''" 1e999 1.5.3m m 99999999999999999999h; do
  i=$((i+1))
  if [ $i = 40 ]; then run_case X0$i cli either "time-limit;duration" "$SQ -o o/X0$i --time-limit $v"
  else run_case X0$i cli reject "time-limit;duration" "$SQ -o o/X0$i --time-limit $v"; fi
done
run_case X041 cli reject 'jobs|-j;-1|negative|NONNEGATIVE|≥' "$SQ -o o/X041 -j -1"
run_case X042 cli reject 'jobs|-j;abc|integer|INT' "$SQ -o o/X042 -j abc"
run_case X043 cli either 'jobs|-j' "cdpowder sweep $IN/sw/valid1.toml -q -o o/X043 -j 0"
run_case X044 cli either 'jobs|-j' "cdpowder sweep $IN/sw/valid1.toml -q -o o/X044 -j 1000000"
run_case X045 cli reject 'task;99999|range|runs' "$SQ -o o/X045 --task 99999"
run_case X046 cli reject 'task;-1|negative|UINT|≥' "$SQ -o o/X046 --task -1"
run_case X047 cli reject 'list;collect|exclude' "$SQ -o o/X047 --list --collect"
run_case X048 cli reject 'folder|exist;/nonexist' "cdpowder resume /nonexist"
run_case X049 cli reject 'checkpoint' "cdpowder resume $W/o"
PRE='cdpowder simulate "$Q" -q -o "$W/o/X050" --set contact.mu_roll=0 --set contact.mu_twist=0 --set run.until_blocked=false --set run.duration=200 --checkpoint-every 1 >/dev/null 2>&1 & p=$!; sleep 0.6; kill -KILL "$p"; wait "$p" 2>/dev/null; f=$W/o/X050/checkpoint.cdps; [ -f "$f" ] && truncate -s $(( $(stat -c %s "$f") / 2 )) "$f"'
run_case X050 cli reject 'checkpoint\.cdps;byte|truncated|damaged|checksum' "cdpowder resume o/X050 -q"
PRE='mkdir -p "$W/o/X051"; head -c 5000 /dev/urandom > "$W/o/X051/checkpoint.cdps"; cp "$LP" "$W/o/X051/initial_particles.csv"'
run_case X051 cli reject 'checkpoint\.cdps;byte|not a state|damaged|CDPSTATE' "cdpowder resume o/X051 -q"
PRE='mkdir -p "$W/o/X052"; : > "$W/o/X052/checkpoint.cdps"'
run_case X052 cli reject 'checkpoint\.cdps;byte|empty|truncated|not a state' "cdpowder resume o/X052 -q"
run_case X053 cli reject 'out|required' "cdpowder compact $Q -q"
run_case X054 cli reject 'extra|unexpected|argument|positional' "cdpowder compact $Q $Q -q -o o/X054"
run_case X055 cli reject 'set|argument|value|expected' "cdpowder compact $Q -q -o o/X055 --set"
run_case X056 cli reject 'unknown|unrecognized|--frobnicate' "cdpowder compact $Q -q -o o/X056 --frobnicate"
PRE='mkdir -p "$W/o/X057"; (cdpowder simulate "$Q" -q -o "$W/o/X057" --set contact.mu_roll=0 --set contact.mu_twist=0 --set run.until_blocked=false --set run.duration=200 --checkpoint-every 1 >/dev/null 2>&1 & p=$!; sleep 0.6; kill -KILL "$p"; wait "$p" 2>/dev/null); rm -f "$W/o/X057/initial_particles.csv"'
POST='grep -a -q -- "--particles" "$W/logs/X057.err" && NOTE="$NOTE; names the file and says no such file, but attributes it to --particles/particles.file, which a resume user never gave"'
run_case X057 cli reject 'initial_particles|cannot|missing' "cdpowder resume o/X057 -q"
run_case X059 cli either 'checkpoint-every;1e-05' "cdpowder simulate $Q -q -o o/X059 --set run.until_blocked=false --set run.duration=1 --checkpoint-every 1e-5" 30
run_case X060 cli either 'checkpoint-every;1e-07' "cdpowder simulate $Q -q -o o/X060 --set run.until_blocked=false --set run.duration=1 --checkpoint-every 1e-7" 30
run_case X058 cli reject 'checkpoint-every|argument|expected' "cdpowder compact $Q -q -o o/X058 --checkpoint-every"

###########################################################################################
# 3. signals
###########################################################################################
# start a command in the background (own process group); sets BGPID
bg_start() { bash -c "exec $1" </dev/null >"$2.out" 2>"$2.err" & BGPID=$!; BGT0=$(now); }
# wait for BGPID up to $1 s (then SIGKILL); sets BGRC, BGEND
bg_wait() {
  local max=$1 i=0
  ( sleep "$max"; kill -KILL $BGPID 2>/dev/null ) & local wd=$!
  wait $BGPID; BGRC=$?; BGEND=$(now)
  kill -- -$wd 2>/dev/null; kill $wd 2>/dev/null; wait $wd 2>/dev/null
}
# wait until file $1 holds regex $2, up to $3 s
wait_for() { local i; for i in $(seq 1 $(( $3 * 20 ))); do grep -a -q -E "$2" "$1" 2>/dev/null && return 0; sleep 0.05; done; return 1; }
orphans() { pgrep -f -- "$1" | grep -v "^$$\$" | tr '\n' ' '; }

# sig_run ID SIGNAL DELAY CMD DIR -> sets RC, DT (signal -> exit), WALL
sig_run() {
  local id=$1 sig=$2 delay=$3 cmd=$4
  bg_start "$cmd" "$W/logs/$id"
  sleep "$delay"
  local ts; ts=$(now)
  kill -s "$sig" $BGPID
  bg_wait 120
  RC=$BGRC; DT=$(secs "$ts" "$BGEND"); WALL=$(secs "$BGT0" "$BGEND")
}
sig_common() {  # checks on the run's exit; args: ERRFILE
  generic_checks "$RC" "$1" 120
  awk -v d="$DT" 'BEGIN{exit !(d > 2.5)}' && worse unclear "signal to exit took ${DT}s (> 2.5 s)"
  NOTE="$NOTE; signal->exit ${DT}s"
}
sig_category_enabled() { case "$ONLY" in all|sig) return 0;; *) return 1;; esac; }

if sig_category_enabled; then
  # reference: the quick scene at (0,0), uninterrupted (≈3 s)
  REFCMD="cdpowder compact $Q -q --set contact.mu_roll=0 --set contact.mu_twist=0"
  cdpowder compact "$Q" -q --set contact.mu_roll=0 --set contact.mu_twist=0 -o "$W/o/sref" >/dev/null 2>&1
  REFPOR=$(summary_porosity "$W/o/sref"); REFMD5=$(md5sum < "$W/o/sref/particles.csv")

  # S001-S003: SIGINT/SIGTERM/SIGHUP during a compaction, then resume to the end (bit-identical?)
  n=0
  for sig in INT TERM HUP; do
    n=$((n+1)); id=S00$n; V=ok; NOTE=""
    cmd="$REFCMD -o o/$id"
    sig_run $id $sig 1.2 "$cmd"
    sig_common "$W/logs/$id.err"
    [ "$RC" -eq 1 ] || worse unclear "exit $RC (docs: interrupted -> 1)"
    it=$(fmt json "o/$id/summary.json" run.interrupted)
    [ "$it" = true ] || worse unclear "summary.json run.interrupted = $it"
    grep -a -q -i 'interrupt\|stopped' "$W/logs/$id.err" || worse unclear "stderr does not say interrupted"
    [ -f "o/$id/checkpoint.cdps" ] || worse unclear "no checkpoint.cdps"
    timeout 120 cdpowder resume o/$id -q >"$W/logs/$id.resume.out" 2>"$W/logs/$id.resume.err"; rrc=$?
    rpor=$(summary_porosity o/$id); rmd5=$(md5sum < o/$id/particles.csv)
    [ $rrc -ge 128 ] && worse crash "resume killed by signal $((rrc-128))"
    if [ $rrc -ne 0 ]; then worse unclear "resume exit $rrc: $(fmt errline "$W/logs/$id.resume.err" 200)"
    elif [ "$rmd5" != "$REFMD5" ]; then worse unclear "resume finished (porosity $rpor) but particles.csv differs from the uninterrupted run (porosity $REFPOR)"
    else NOTE="$NOTE; resume exit 0, particles.csv identical to the uninterrupted run (porosity $rpor)"; fi
    [ -f "o/$id/checkpoint.cdps" ] && worse unclear "checkpoint.cdps left after the resumed run finished"
    record $id sig "kill -$sig after 1.2 s: $cmd; then cdpowder resume o/$id -q" "$RC" "$WALL" "$W/logs/$id.err" "$V" "$NOTE"
  done

  # S004 (SIGINT), S018 (SIGHUP): during a 1e6-sphere deposit (deposit command)
  for pair in S004:INT S018:HUP; do
    id=${pair%%:*}; sig=${pair#*:}; V=ok; NOTE=""
    cmd="cdpowder deposit $PAPER -o o/$id --set deposition.spheres=1000000 --set system.lx=800 --set system.ly=800"
    sig_run $id "$sig" 1.0 "$cmd"; sig_common "$W/logs/$id.err"
    [ "$RC" -eq 1 ] || worse unclear "exit $RC (docs: 1)"
    grep -a -q -i 'interrupt\|stopped' "$W/logs/$id.err" || worse unclear "stderr does not say interrupted"
    NOTE="$NOTE; folder after: [$(listing "o/$id")]"
    record $id sig "kill -$sig after 1.0 s: $cmd" "$RC" "$WALL" "$W/logs/$id.err" "$V" "$NOTE"
  done

  # S005: SIGTERM during the deposition phase of a compact (1e6 spheres); resume must refuse cleanly
  id=S005; V=ok; NOTE=""
  cmd="cdpowder compact $PAPER -q -o o/$id --set deposition.spheres=1000000 --set system.lx=800 --set system.ly=800"
  sig_run $id TERM 1.0 "$cmd"; sig_common "$W/logs/$id.err"
  [ "$RC" -eq 1 ] || worse unclear "exit $RC (docs: 1)"
  grep -a -q -i 'interrupt\|stopped' "$W/logs/$id.err" || worse unclear "stderr does not say interrupted"
  NOTE="$NOTE; folder after: [$(listing "o/$id")]"
  timeout 60 cdpowder resume o/$id -q >"$W/logs/$id.resume.out" 2>"$W/logs/$id.resume.err"; rrc=$?
  [ $rrc -ge 128 ] && worse crash "resume killed by signal"
  NOTE="$NOTE; resume exit $rrc: $(fmt errline "$W/logs/$id.resume.err" 200)"
  record $id sig "kill -TERM after 1.0 s: $cmd; then cdpowder resume o/$id" "$RC" "$WALL" "$W/logs/$id.err" "$V" "$NOTE"

  # S006: SIGINT during a 60000-sphere compaction; then resume, SIGINT the resume after it started
  for pair in "S006 INT" "S007 TERM" "S008 HUP"; do
    id=${pair% *}; sig=${pair#* }; V=ok; NOTE=""
    cmd="cdpowder compact $PAPER -q -o o/$id --set deposition.spheres=60000 --set system.lx=200 --set system.ly=200"
    sig_run "$id" "$sig" 6 "$cmd"; sig_common "$W/logs/$id.err"
    [ "$RC" -eq 1 ] || worse unclear "exit $RC (docs: 1)"
    it=$(fmt json "o/$id/summary.json" run.interrupted)
    [ "$it" = true ] || worse unclear "summary.json run.interrupted = $it"
    [ -f "o/$id/checkpoint.cdps" ] || worse unclear "no checkpoint.cdps"
    NOTE="$NOTE; steps at stop: $(fmt json "o/$id/summary.json" run.steps)"
    if [ "$id" = S006 ]; then
      bg_start "cdpowder resume o/$id -q" "$W/logs/$id.resume"
      if wait_for "$W/logs/$id.resume.err" 'resume from step' 30; then sleep 3; fi
      t1=$(now); kill -INT $BGPID; bg_wait 120; rdt=$(secs "$t1" "$BGEND")
      [ $BGRC -ge 128 ] && worse crash "resume killed by signal"
      if [ $BGRC -eq 1 ] && [ "$(fmt json "o/$id/summary.json" run.interrupted)" = true ] && grep -a -q 'resume from step' "$W/logs/$id.resume.err"; then
        NOTE="$NOTE; resume started ($(grep -a -o 'resume from step [0-9]*' "$W/logs/$id.resume.err")), stopped again by SIGINT in ${rdt}s, steps now $(fmt json "o/$id/summary.json" run.steps)"
      else worse unclear "resume: exit $BGRC, $(fmt errline "$W/logs/$id.resume.err" 200)"; fi
    fi
    record "$id" sig "kill -$sig after 6 s: $cmd$([ "$id" = S006 ] && echo "; then cdpowder resume o/$id -q, SIGINT 3 s after it started")" "$RC" "$WALL" "$W/logs/$id.err" "$V" "$NOTE"
  done

  # S009: two SIGINTs 0.2 s apart during a 60000-sphere compaction
  id=S009; V=ok; NOTE=""
  cmd="cdpowder compact $PAPER -q -o o/$id --set deposition.spheres=60000 --set system.lx=200 --set system.ly=200"
  bg_start "$cmd" "$W/logs/$id"; sleep 6; ts=$(now); kill -INT $BGPID; sleep 0.2; kill -INT $BGPID 2>/dev/null; bg_wait 120
  RC=$BGRC; DT=$(secs "$ts" "$BGEND"); WALL=$(secs "$BGT0" "$BGEND"); sig_common "$W/logs/$id.err"
  # the second SIGINT is documented to end the program at once: a death by SIGINT (130) is the
  # intended outcome here, not a crash, as long as the folder can be resumed (checked below)
  if [ "$RC" -eq 130 ]; then V=ok; NOTE="$NOTE; exit 130 = died of the 2nd SIGINT as documented ('a second Ctrl-C ends the program at once')"; fi
  NOTE="$NOTE; folder after: [$(listing "o/$id")]"
  tmpc=$(find "o/$id" -mindepth 1 -maxdepth 1 -iname '*tmp*' | wc -l)
  [ "$tmpc" -gt 0 ] && NOTE="$NOTE; $tmpc temporary files left"
  bg_start "cdpowder resume o/$id -q" "$W/logs/$id.resume"; sleep 4; kill -INT $BGPID 2>/dev/null; bg_wait 120; rrc=$BGRC
  [ $rrc -ge 128 ] && worse crash "resume killed by signal $((rrc-128))"
  NOTE="$NOTE; resume then: exit $rrc $(fmt errline "$W/logs/$id.resume.err" 200)"
  grep -a -q 'resume from step' "$W/logs/$id.resume.err" || worse unclear "the folder left by the 2nd SIGINT cannot be resumed"
  record $id sig "kill -INT twice (0.2 s apart) after 6 s: $cmd; then cdpowder resume o/$id (SIGINT after 4 s)" "$RC" "$WALL" "$W/logs/$id.err" "$V" "$NOTE"

  # sweeps: 2 points x 2 seeds of the quick scene at mu_twist=0, -j 2
  printf 'scene = "%s"\nseeds = 2\n[grid.contact]\nmu_roll = [0.0, 1.0]\nmu_twist = [0.0]\n' "$Q" > "$IN/sw_sig.toml"
  n=9
  for sig in INT TERM HUP; do
    n=$((n+1)); id=S0$n; V=ok; NOTE=""
    cmd="cdpowder sweep $IN/sw_sig.toml -o $W/o/$id -j 2"
    sig_run $id $sig 2.5 "$cmd"; sig_common "$W/logs/$id.err"
    [ "$RC" -eq 1 ] || worse unclear "exit $RC (docs: 1)"
    sleep 0.5; orph=$(orphans "$W/o/$id")
    [ -n "$orph" ] && worse lost "cdpowder processes left after the sweep exited: $orph"
    ni=$(grep -l '"interrupted": true' "$W/o/$id/runs/"*/seed_*/summary.json 2>/dev/null | wc -l)
    nf=$(grep -l '"interrupted": false' "$W/o/$id/runs/"*/seed_*/summary.json 2>/dev/null | wc -l)
    NOTE="$NOTE; last line (stdout): $(tail -1 "$W/logs/$id.out" | cut -c1-160); runs interrupted=$ni finished=$nf; results.csv $( [ -f "$W/o/$id/results.csv" ] && echo present || echo absent)"
    [ "$ni" -ge 1 ] || worse unclear "no run says interrupted"
    if [ $sig = INT ]; then
      timeout 120 cdpowder sweep "$IN/sw_sig.toml" -o "$W/o/$id" --dry-run >"$W/logs/$id.dry.out" 2>&1
      NOTE="$NOTE; dry-run: $(grep -c '^resume' "$W/logs/$id.dry.out") resume, $(grep -c '^done' "$W/logs/$id.dry.out") done, $(grep -c '^pending' "$W/logs/$id.dry.out") pending"
      timeout 120 cdpowder sweep "$IN/sw_sig.toml" -o "$W/o/$id" -j 2 -q >"$W/logs/$id.rerun.out" 2>"$W/logs/$id.rerun.err"; rrc=$?
      if [ $rrc -eq 0 ]; then NOTE="$NOTE; rerun exit 0: $(tail -1 "$W/logs/$id.rerun.err" | cut -c1-120)"
      else worse unclear "rerun exit $rrc $(fmt errline "$W/logs/$id.rerun.err" 200)"; fi
    fi
    record $id sig "kill -$sig after 2.5 s: $cmd$([ $sig = INT ] && echo "; then the same command --dry-run and again")" "$RC" "$WALL" "$W/logs/$id.err" "$V" "$NOTE"
  done

  # S013: SIGKILL of a sweep: the runs must not be left running
  id=S013; V=ok; NOTE=""
  cmd="cdpowder sweep $IN/sw_sig.toml -o $W/o/$id -j 2"
  bg_start "$cmd" "$W/logs/$id"; sleep 2.5
  before=$(orphans "$W/o/$id"); ts=$(now); kill -KILL $BGPID; bg_wait 10; RC=$BGRC; WALL=$(secs "$BGT0" "$BGEND")
  gone=""
  for i in $(seq 1 100); do [ -z "$(orphans "$W/o/$id")" ] && { gone=$(secs "$ts" "$(now)"); break; }; sleep 0.1; done
  NOTE="processes before: $(echo "$before" | wc -w)"
  if [ -z "$gone" ]; then worse lost "run processes still alive 10 s after SIGKILL of the sweep: $(orphans "$W/o/$id")"; for p in $(orphans "$W/o/$id"); do kill -TERM "$p" 2>/dev/null; done
  else NOTE="$NOTE; all run processes gone ${gone}s after SIGKILL of the sweep"; fi
  ni=$(grep -l '"interrupted": true' "$W/o/$id/runs/"*/seed_*/summary.json 2>/dev/null | wc -l)
  NOTE="$NOTE; runs flagged interrupted: $ni"
  timeout 120 cdpowder sweep "$IN/sw_sig.toml" -o "$W/o/$id" -j 2 -q >"$W/logs/$id.rerun.out" 2>"$W/logs/$id.rerun.err"; rrc=$?
  if [ $rrc -eq 0 ]; then NOTE="$NOTE; rerun exit 0"
  else worse unclear "rerun after SIGKILL exit $rrc: $(fmt errline "$W/logs/$id.rerun.err" 200)"; fi
  record $id sig "kill -KILL after 2.5 s: $cmd; pgrep -f $W/o/$id; then the same command again" "$RC" "$WALL" "$W/logs/$id.err" "$V" "$NOTE"

  # S014: SIGINT to a resume; then resume again to the end (bit-identical?)
  id=S014; V=ok; NOTE=""
  sig_run ${id}a INT 0.8 "$REFCMD -o o/$id"
  sig_run $id INT 0.8 "cdpowder resume o/$id -q"
  sig_common "$W/logs/$id.err"
  [ "$RC" -eq 1 ] || worse unclear "resume exit $RC on SIGINT (docs: 1)"
  timeout 120 cdpowder resume o/$id -q >"$W/logs/$id.resume.out" 2>"$W/logs/$id.resume.err"; rrc=$?
  if [ $rrc -eq 0 ] && [ "$(md5sum < o/$id/particles.csv)" = "$REFMD5" ]; then NOTE="$NOTE; second resume exit 0, identical to the uninterrupted run"
  else worse unclear "second resume exit $rrc, porosity $(summary_porosity o/$id) vs $REFPOR"; fi
  record $id sig "$REFCMD -o o/$id; SIGINT at 0.8 s; cdpowder resume o/$id -q; SIGINT at 0.8 s; cdpowder resume o/$id -q" "$RC" "$WALL" "$W/logs/$id.err" "$V" "$NOTE"

  # S015: SIGKILL of a compaction with --checkpoint-every, then resume (bit-identical?)
  id=S015; V=ok; NOTE=""
  cmd="$REFCMD -o o/$id --checkpoint-every 20"
  sig_run $id KILL 1.5 "$cmd"
  [ "$RC" -eq 137 ] && NOTE="killed as intended (137)"
  [ -f "o/$id/checkpoint.cdps" ] || worse unclear "no checkpoint after SIGKILL"
  timeout 120 cdpowder resume o/$id -q >"$W/logs/$id.resume.out" 2>"$W/logs/$id.resume.err"; rrc=$?
  if [ $rrc -eq 0 ] && [ "$(md5sum < o/$id/particles.csv)" = "$REFMD5" ]; then NOTE="$NOTE; resume exit 0, identical to the uninterrupted run"
  else worse unclear "resume exit $rrc, porosity $(summary_porosity o/$id) vs $REFPOR: $(fmt errline "$W/logs/$id.resume.err" 200)"; fi
  record $id sig "kill -KILL after 1.5 s: $cmd; then cdpowder resume o/$id -q" "$RC" "$WALL" "$W/logs/$id.resume.err" "$V" "$NOTE"

  # S016: SIGTERM to a sweep --task (a scheduler's limit); the same --task again continues
  id=S016; V=ok; NOTE=""
  cmd="cdpowder sweep $IN/sw_sig.toml -o $W/o/$id --task 0 -q"
  sig_run $id TERM 1.0 "$cmd"; sig_common "$W/logs/$id.err"
  [ "$RC" -eq 1 ] || worse unclear "exit $RC (docs: 1)"
  timeout 120 cdpowder sweep "$IN/sw_sig.toml" -o "$W/o/$id" --task 0 -q >"$W/logs/$id.rerun.out" 2>"$W/logs/$id.rerun.err"; rrc=$?
  if [ $rrc -eq 0 ]; then NOTE="$NOTE; --task 0 again: exit 0 ($(grep -a -c 'resume from step' "$W/o/$id/runs/"*/seed_1/log.txt) resume line in log.txt)"
  else worse unclear "--task 0 again: exit $rrc"; fi
  record $id sig "kill -TERM after 1.0 s: $cmd; then the same command again" "$RC" "$WALL" "$W/logs/$id.err" "$V" "$NOTE"

  # S017: --time-limit 3 on a sweep whose runs take longer: the runs stop as at Ctrl-C
  id=S017; V=ok; NOTE=""
  cmd="cdpowder sweep $IN/sw_sig.toml -o $W/o/$id -j 2 --time-limit 2"
  bg_start "$cmd" "$W/logs/$id"; bg_wait 120; RC=$BGRC; WALL=$(secs "$BGT0" "$BGEND"); DT=0
  generic_checks "$RC" "$W/logs/$id.err" 120
  [ "$RC" -eq 1 ] || worse unclear "exit $RC (docs: 1 unless every run finished)"
  awk -v w="$WALL" 'BEGIN{exit !(w > 5)}' && worse unclear "a 2 s time limit took ${WALL}s"
  NOTE="$NOTE; last line (stdout): $(tail -1 "$W/logs/$id.out" | cut -c1-200); orphans: [$(orphans "$W/o/$id")]"
  record $id sig "$cmd" "$RC" "$WALL" "$W/logs/$id.err" "$V" "$NOTE"

  # S018: GNU timeout's stop: SIGINT to the run and then to its process group (twice in a few
  # microseconds); every output and a checkpoint must be written (a second delivery once
  # ended the program with nothing but scene.toml and initial_particles.csv)
  id=S018; V=ok; NOTE=""
  cmd="timeout --preserve-status -s INT 1.5 cdpowder compact $Q -q -o $W/o/$id --set run.max_duration=1e5 --set run.blocked.piston_speed=1e-300"
  bg_start "$cmd" "$W/logs/$id"; bg_wait 120; RC=$BGRC; WALL=$(secs "$BGT0" "$BGEND")
  generic_checks "$RC" "$W/logs/$id.err" 120
  [ "$RC" -eq 1 ] || worse unclear "exit $RC (docs: 1, interrupted)"
  for f in summary.json particles.csv contacts.csv timeseries.csv particles.vtp checkpoint.cdps; do
    [ -f "$W/o/$id/$f" ] || worse lost "$f missing after the stop"
  done
  NOTE="$NOTE; folder after: [$(listing "$W/o/$id")]"
  record $id sig "$cmd" "$RC" "$WALL" "$W/logs/$id.err" "$V" "$NOTE"
fi

NOW_SHA=$(sha256sum < "$SRC_BIN" 2>/dev/null | cut -d' ' -f1)
if [ "$NOW_SHA" = "$BIN_SHA" ]; then same="unchanged"; else same="changed since the copy: sha256 ${NOW_SHA:-(gone)}"; fi
echo "end: $(date -Is); $SRC_BIN $same" >> "$OUTDIR/probe_info.txt"
echo
echo "results: $RES ($(($(wc -l < "$RES") - 1)) cases); binary $(sed -n 's/^version: //p' "$OUTDIR/probe_info.txt")"
echo
fmt summary "$RES" | tee "$OUTDIR/summary.txt"
exit "${PIPESTATUS[0]}"
