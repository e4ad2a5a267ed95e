"""cdpowder.protocol: one run of a sweep's Python protocol (docs/sweeps.md, "A Python protocol").

A sweep file with `command = "python"` and `protocol = "FILE.py:FUNCTION"` runs each point and
seed as

    python3 -m cdpowder.protocol FILE.py FUNCTION SCENE --out DIR [--set KEY=VALUE ...]

which reads SCENE with the point's overrides (the --set values are TOML, as on the command
line), calls FUNCTION(scene, out) with the cdpowder.Scene and the run's folder (a
pathlib.Path), and records the run as finished in DIR/protocol.json once the function has
returned. The function runs the engine as it likes (compact, simulate, World.run, several
stages); its last stage writes the run's files into `out` (`out=out`), and the sweep's tables
read that summary.json. The function may return a dict of JSON values, kept in protocol.json
under "returned".

Exit status: 0 when the function returned and DIR/summary.json is a finished run's; 3 when a
fault stopped a run (cdpowder.RunFailed); 130 when interrupted (Ctrl-C or SIGTERM: a sweep's
stop); 2 for a mistake in the arguments, the scene or the protocol's name; 1 otherwise (the
traceback is printed).
"""
import argparse
import importlib.util
import json
import os
import pathlib
import signal
import sys
import tomllib

from cdpowder import summary as summaries

RECORD = "protocol.json"  # kProtocolRecordFile of src/cdpowder/study/protocol_record.hpp
EXIT_USAGE, EXIT_FAULT, EXIT_INTERRUPTED = 2, 3, 130


class ProtocolError(Exception):
    """A mistake in the arguments, the overrides or the protocol's file or function."""


def parse_override(text):
    """("contact.mu", 0.3) from "contact.mu=0.3": the value is TOML, as `--set` reads it."""
    key, sep, value = text.partition("=")
    if not sep or not key.strip():
        raise ProtocolError(f"--set {text}: expected KEY=VALUE")
    try:
        return key.strip(), tomllib.loads(f"v = {value}")["v"]
    except tomllib.TOMLDecodeError as error:
        raise ProtocolError(f"--set {text}: the value is not TOML ({error})") from None


def load_function(file, name):
    """The function `name` of the Python file `file`."""
    path = pathlib.Path(file)
    if not path.is_file():
        raise ProtocolError(f"{file}: no such file")
    spec = importlib.util.spec_from_file_location(f"cdpowder_protocol_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    sys.path.insert(0, str(path.resolve().parent))  # the protocol's own imports beside it
    spec.loader.exec_module(module)
    function = getattr(module, name, None)
    if not callable(function):
        raise ProtocolError(f"{file}: has no function {name!r}")
    return function


def write_record(out, name, scene_toml, returned):
    """protocol.json, atomically: the protocol, the point's scene, what the function returned."""
    record = {"protocol": name, "scene": scene_toml}
    if returned is not None:
        try:
            json.dumps(returned)
            record["returned"] = returned
        except TypeError:
            record["returned"] = repr(returned)
    partial = out / f".{RECORD}.partial"
    partial.write_text(json.dumps(record, indent=2) + "\n")
    os.replace(partial, out / RECORD)


def finished_summary(out):
    """The run's summary.json; ProtocolError when the protocol wrote none."""
    path = out / "summary.json"
    if not path.is_file():
        raise ProtocolError(f"the protocol wrote no {path}: run its last stage with out=out")
    return summaries.read_summary(path)


def _stop_on_sigterm(signum, frame):
    raise KeyboardInterrupt(f"signal {signum}")


def main(argv=None):
    """Runs one point of a sweep's protocol; returns the exit status."""
    parser = argparse.ArgumentParser(prog="python3 -m cdpowder.protocol",
                                     description="One run of a sweep's Python protocol.")
    parser.add_argument("file", help="the Python file that holds the protocol")
    parser.add_argument("function", help="the function: FUNCTION(scene, out)")
    parser.add_argument("scene", help="the point's base scene (TOML)")
    parser.add_argument("--out", required=True, help="the run's folder")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="a scene override, as on the command line")
    parser.add_argument("--name", help="the protocol's name in protocol.json (FILE:FUNCTION)")
    args = parser.parse_args(argv)
    name = args.name or f"{args.file}:{args.function}"
    out = pathlib.Path(args.out)
    import cdpowder  # after the arguments: --help works without the engine

    try:
        overrides = dict(parse_override(text) for text in args.set)
        scene = cdpowder.Scene.from_toml(args.scene, overrides)
        function = load_function(args.file, args.function)
    except (ProtocolError, cdpowder.ConfigError) as error:
        print(f"error: {error}", file=sys.stderr)
        return EXIT_USAGE
    out.mkdir(parents=True, exist_ok=True)
    (out / RECORD).unlink(missing_ok=True)  # finished again only when this run returns
    signal.signal(signal.SIGTERM, _stop_on_sigterm)
    try:
        returned = function(scene, out)
        summary = finished_summary(out)
    except cdpowder.RunFailed as error:
        print(f"error: {error}", file=sys.stderr)
        return EXIT_FAULT
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except (ProtocolError, summaries.SummaryError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    run = summary.get("run", {})
    if run.get("interrupted") or run.get("failed"):
        print(f"error: {out / 'summary.json'} is of a run that did not finish", file=sys.stderr)
        return EXIT_INTERRUPTED if run.get("interrupted") else EXIT_FAULT
    write_record(out, name, scene.toml, returned)
    print(f"protocol {name}: finished; porosity={summary.get('porosity')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
