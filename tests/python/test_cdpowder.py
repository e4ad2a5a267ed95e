"""`import cdpowder` (python/cdpowder_module.cpp): the same numbers as the command line, the
state as NumPy views, callbacks that can stop a run, errors with the command line's messages.
Run by ctest (python_module_test) with PYTHONPATH at the build tree's module; needs
CDPOWDER_EXE (the program) and CDPOWDER_SOURCE_DIR in the environment."""
import json
import os
import signal
import subprocess
from pathlib import Path

import numpy as np
import pytest

import cdpowder

SOURCE = Path(os.environ["CDPOWDER_SOURCE_DIR"])
QUICK = SOURCE / "examples/quick/scene.toml"
SHORT = {"run.max_duration": 5.0}  # the quick compaction's first 500 steps


def quick(**overrides):
    return cdpowder.Scene.from_toml(QUICK, {**SHORT, **overrides})


def test_a_compaction_gives_the_command_lines_numbers(tmp_path):
    scene = quick(**{"contact.mu_roll": 0.3})
    result = cdpowder.compact(scene, out=tmp_path / "py")
    cli = subprocess.run([os.environ["CDPOWDER_EXE"], "compact", str(QUICK), "--out",
                          str(tmp_path / "cli"), "--quiet", "--set", "run.max_duration=5.0",
                          "--set", "contact.mu_roll=0.3"], capture_output=True, text=True)
    assert cli.returncode == 4, cli.stderr  # not blocked within the short duration
    summary = json.loads((tmp_path / "cli" / "summary.json").read_text())
    assert result.porosity == summary["porosity"]
    assert result.steps == summary["run"]["steps"]
    assert result.blocked is False
    assert result.summary["porosity"] == summary["porosity"]
    # the library wrote the command line's files, the same particles to the last digit
    assert (tmp_path / "py" / "particles.csv").read_text().split("\n")[3:] == \
        (tmp_path / "cli" / "particles.csv").read_text().split("\n")[3:]
    assert cli.stdout.strip().split(" wall=")[0] == result.line.split(" wall=")[0]


def test_the_stress_comes_in_3_by_3_parts_that_add_up():
    result = cdpowder.compact(quick())
    for tensor in (result.sigma, result.sigma_plus, result.sigma_minus):
        assert tensor.shape == (3, 3)
    np.testing.assert_allclose(result.sigma_plus + result.sigma_minus, result.sigma, atol=1e-15)
    assert result.sigma_plus[2, 2] >= 0.0 >= result.sigma_minus[2, 2]


def test_the_state_is_a_view_of_the_world_without_a_copy():
    world = cdpowder.deposit(quick())
    positions = world.positions
    assert positions.shape == (len(world), 3) and world.radii.shape == (len(world),)
    assert not positions.flags["OWNDATA"]
    assert np.all(world.radii == 1.0)
    assert np.all(positions[:, 2] >= world.radii - 1e-9)  # above the bottom wall
    # the same memory, seen again
    assert world.positions.__array_interface__["data"][0] == \
        positions.__array_interface__["data"][0]
    before = positions.copy()
    porosity_before = world.porosity
    result = cdpowder.compact(quick(), world=world)
    # the compaction continued this world: the old view shows its new positions
    assert result.world.positions.__array_interface__["data"][0] == \
        positions.__array_interface__["data"][0]
    assert not np.array_equal(positions, before)
    assert result.porosity < porosity_before
    assert positions.base is not None  # still valid: it keeps the world alive


def test_a_callback_runs_every_k_steps_and_can_stop_the_run():
    seen = []

    def every_100(world, step):
        seen.append((world.step_count, step.contacts))
        return len(seen) < 3  # False: stop

    result = cdpowder.compact(quick(), callback=every_100, every=100)
    assert [s for s, _ in seen] == [100, 200, 300]
    assert result.interrupted and result.steps == 300


def test_an_exception_in_the_callback_ends_the_run_and_arrives_in_python():
    def broken(world, step):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        cdpowder.compact(quick(), callback=broken, every=10)


def test_bad_input_raises_with_the_command_lines_message(tmp_path):
    with pytest.raises(cdpowder.ConfigError, match=r"contact\.mu_roll: got -0\.2, expected a number ≥ 0"):
        cdpowder.Scene.from_toml(QUICK, {"contact.mu_roll": -0.2})
    with pytest.raises(cdpowder.ConfigError, match="unknown key; did you mean 'solver.tolerance'"):
        cdpowder.Scene.from_toml(QUICK, {"solver.tolerence": 1e-6})
    with pytest.raises(ValueError):  # ConfigError is a ValueError
        cdpowder.Scene.from_toml(tmp_path / "missing.toml")
    with pytest.raises(cdpowder.ConfigError, match="contact.mu: got an array, expected a number"):
        cdpowder.Scene.from_toml(QUICK, {"contact.mu": [0.3]})
    with pytest.raises(TypeError, match="expected a bool, an int, a float, a str or a list"):
        cdpowder.Scene.from_toml(QUICK, {"contact.mu": {"a": 1}})


def test_overrides_keep_their_types_and_the_seed():
    scene = quick(**{"solver.seed": 7, "run.vtk_format": "binary", "solver.warm_start": True})
    assert scene.seed == 7
    assert 'vtk_format = "binary"' in scene.toml
    again = scene.with_overrides({"solver.seed": 8})
    assert again.seed == 8 and scene.seed == 7


def test_ctrl_c_ends_the_run_cleanly_and_raises_keyboard_interrupt(tmp_path):
    def press_ctrl_c(world, step):
        os.kill(os.getpid(), signal.SIGINT)  # as a Ctrl-C at the terminal would

    with pytest.raises(KeyboardInterrupt):
        cdpowder.compact(quick(), callback=press_ctrl_c, every=50, out=tmp_path)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["run"]["interrupted"] is True
    assert summary["run"]["steps"] == 50  # stopped after the step that saw the signal


def test_a_scene_built_in_code_runs_like_one_read_from_a_file(tmp_path):
    keys = {"deposition.spheres": 100, "deposition.capture_radius": 3.0, "system.lx": 10.0,
            "system.ly": 10.0, "contact.cohesion_range": 0.05, "piston.enabled": True,
            "piston.pressure": 0.0025, "piston.start_gap": 0.5, "run.until_blocked": True,
            "run.max_duration": 5.0}
    in_code = cdpowder.Scene.from_keys(keys)
    assert "[deposition]" in in_code.toml and "spheres = 100" in in_code.toml
    # the same scene as a file gives the same run
    (tmp_path / "scene.toml").write_text(in_code.toml)
    from_file = cdpowder.Scene.from_toml(tmp_path / "scene.toml")
    assert cdpowder.compact(in_code).porosity == cdpowder.compact(from_file).porosity
    with pytest.raises(cdpowder.ConfigError, match="deposition.spheres"):
        cdpowder.Scene.from_keys({**keys, "deposition.spheres": 0})


def test_a_world_from_arrays_compacts_like_the_deposit_it_copies():
    scene = quick()
    deposit = cdpowder.deposit(scene)
    copy = cdpowder.World.from_arrays(scene, deposit.positions.copy(), deposit.radii.copy())
    assert len(copy) == len(deposit) and copy.piston_height == deposit.piston_height
    assert copy.positions.flags["C_CONTIGUOUS"] and not copy.positions.flags["OWNDATA"]
    # the same spheres, walls, piston and seed: the same run, bit for bit
    assert cdpowder.compact(scene, world=copy).porosity == \
        cdpowder.compact(scene, world=deposit).porosity
    # lists are arrays too; velocities and fixed spheres are taken as given
    moving = cdpowder.World.from_arrays(
        scene, [[1.0, 1.0, 1.0], [4.0, 1.0, 1.0]], [1.0, 1.0],
        velocities=[[0.0, 0.0, 0.5], [0.0, 0.0, 0.0]], fixed=[False, True])
    assert moving.velocities[0, 2] == 0.5 and moving.piston_height == 2.0 + 0.0
    assert cdpowder.simulate(scene.with_overrides({"run.max_duration": 0.5}),
                             world=moving).world.positions[1, 2] == 1.0  # fixed: never moves


def test_bad_arrays_are_named_with_the_entry_and_what_is_allowed():
    scene = quick()
    good = np.array([[1.0, 1.0, 1.0], [4.0, 1.0, 1.0]])
    cases = [((good[:, :2], [1.0, 1.0]), r"positions: got an array of shape \(2, 2\), expected \(2, 3\)"),
             ((good, [1.0, -1.0]), r"radii\[1\]: got -1, expected a finite number > 0"),
             ((np.where(good == 4.0, np.nan, good), [1.0, 1.0]),
              r"positions\[1, 0\]: got nan, expected a finite number")]
    for (positions, radii), message in cases:
        with pytest.raises(ValueError, match=message):
            cdpowder.World.from_arrays(scene, positions, radii)
    # a sphere too large for the cell: the scene's own check, as a ConfigError
    with pytest.raises(cdpowder.ConfigError, match="system.lx"):
        cdpowder.World.from_arrays(scene, good, [1.0, 8.0])


def test_a_callback_is_judged_by_pythons_truth_and_outputs_are_kept(tmp_path):
    calls = []

    def empty_list_stops(world, step):
        calls.append(world.step_count)
        return [] if len(calls) == 2 else ["go on"]  # a list: its truth decides

    result = cdpowder.compact(quick(), callback=empty_list_stops, every=10, out=tmp_path / "a")
    assert calls == [10, 20] and result.interrupted and result.steps == 20

    class Undecided:
        def __bool__(self):
            raise ValueError("cannot say")

    with pytest.raises(ValueError, match="cannot say"):
        cdpowder.compact(quick(), callback=lambda w, s: Undecided(), every=10, out=tmp_path / "b")
    # the callback's error ends the run with every output written
    for name in ("summary.json", "particles.csv", "contacts.csv", "timeseries.csv"):
        assert (tmp_path / "b" / name).exists(), name
    assert json.loads((tmp_path / "b" / "summary.json").read_text())["run"]["interrupted"]


def test_a_folder_a_run_holds_is_refused_and_left_alone(tmp_path):
    import fcntl
    out = tmp_path / "busy"
    out.mkdir()
    with open(out / ".run.lock", "w") as held:  # another run's lock on the folder
        fcntl.flock(held, fcntl.LOCK_EX | fcntl.LOCK_NB)
        with pytest.raises(RuntimeError, match="is in use by another cdpowder run"):
            cdpowder.compact(quick(), out=out)
    assert sorted(p.name for p in out.iterdir()) == [".run.lock"]


def test_the_engine_steps_without_the_gil():
    import threading
    import time
    ticks = []
    done = threading.Event()

    def tick():
        while not done.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.01)

    ticker = threading.Thread(target=tick)
    ticker.start()
    start = time.monotonic()
    cdpowder.compact(cdpowder.Scene.from_toml(QUICK))  # to its blocked state, ≈ 0.4 s
    seconds = time.monotonic() - start
    done.set()
    ticker.join()
    # a thread ticking every 10 ms ticks through the run (it ticked once in 1.4 s before); the
    # run must be long enough for a held GIL to show
    assert seconds > 0.1, seconds
    assert len(ticks) >= 0.3 * seconds / 0.01, (len(ticks), seconds)


def test_a_world_in_use_refuses_a_second_run():
    world = cdpowder.deposit(quick())

    def compact_again(w, step):
        cdpowder.compact(quick(), world=w)

    with pytest.raises(RuntimeError, match="this World is in use by a run"):
        cdpowder.compact(quick(), world=world, callback=compact_again, every=10)
    result = cdpowder.compact(quick(), world=world)  # free again once the run has ended
    assert result.steps > 0


def test_a_refused_second_run_leaves_the_first_untouched():
    world = cdpowder.deposit(quick())
    refused = []

    def try_again(w, step):
        try:
            cdpowder.compact(quick(), world=w)
        except RuntimeError as error:
            refused.append(str(error))

    # the refused call changed the World's piston and loop state before: the run then failed
    result = cdpowder.compact(quick(), world=world, callback=try_again, every=10)
    assert refused and result.steps == 500


def test_a_world_being_stepped_is_not_read_from_another_thread():
    import threading
    world = cdpowder.deposit(quick())
    seen = {"refused": 0, "read": 0}
    done = threading.Event()

    def reader():
        while not done.is_set():
            try:
                world.contacts()
                seen["read"] += 1
            except RuntimeError as error:
                assert "being stepped by a run on another thread" in str(error)
                seen["refused"] += 1

    thread = threading.Thread(target=reader)
    thread.start()
    cdpowder.compact(quick(), world=world)  # segfaulted with a reader before the guard
    done.set()
    thread.join()
    assert seen["refused"] > 0
    assert len(world.contacts()["a"]) > 0  # free again


def test_a_radius_written_through_a_view_is_a_fault(tmp_path):
    def shrink(world, step):
        world.radii[3] = 0.0

    with pytest.raises(cdpowder.RunFailed, match=r"the radius of sphere 3 is 0, expected a finite number > 0") as failed:
        cdpowder.compact(quick(), callback=shrink, every=10, out=tmp_path)
    assert failed.value.result.steps == 10
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["run"]["failed"] is True and summary["run"]["blocked"] is False


def test_a_world_of_no_spheres_is_refused():
    with pytest.raises(ValueError, match="radii: got 0 spheres, expected at least 1"):
        cdpowder.World.from_arrays(quick(), np.zeros((0, 3)), np.zeros(0))


def test_a_world_stepped_in_pieces_ends_on_the_bits_of_one_compaction():
    scene = quick(**{"contact.mu_roll": 0.3})
    whole = cdpowder.compact(scene)
    world = cdpowder.deposit(scene)
    assert world.last_step is None
    step = world.step()
    assert world.step_count == 1 and step.contacts == world.last_step.contacts
    world.step(9)
    assert world.step_count == 10
    world.run(steps=40)
    world.run(until=world.time + 0.5)
    result = world.run()  # the scene's own end: blocked, or run.max_duration
    assert result.steps == whole.steps and not result.interrupted
    assert np.array_equal(world.positions, whole.world.positions)
    assert np.array_equal(world.angular_velocities, whole.world.angular_velocities)
    assert result.porosity == whole.porosity


def test_save_load_and_pickle_continue_with_the_same_bits(tmp_path):
    import pickle
    scene = quick()
    whole = cdpowder.deposit(scene)
    whole.run(steps=60)
    half = cdpowder.deposit(scene)
    half.run(steps=25)
    half.save(tmp_path / "half.cdps")
    for world in (cdpowder.load(tmp_path / "half.cdps"), pickle.loads(pickle.dumps(half))):
        assert world.step_count == 25 and world.scene["contact.mu"] == scene["contact.mu"]
        world.run(steps=35)
        assert np.array_equal(world.positions, whole.positions)
        assert np.array_equal(world.velocities, whole.velocities)


def test_forces_torques_and_stress_of_any_step():
    world = cdpowder.deposit(quick())
    world.run(steps=30)
    contacts = world.contacts()
    for column in ("tangential_force", "rolling_torque"):
        assert contacts[column].shape == (len(contacts["a"]), 3)
    assert contacts["twisting_torque"].shape == contacts["normal_force"].shape
    np.testing.assert_allclose(
        contacts["force"],
        contacts["normal_force"][:, None] * contacts["normal"] + contacts["tangential_force"])
    forces = world.contact_forces()
    torques = world.contact_torques()
    assert forces.shape == (len(world), 3) and torques.shape == (len(world), 3)
    # action and reaction: the pairs' forces cancel, the walls' remain
    walls = contacts["a"] < 0
    np.testing.assert_allclose(forces.sum(axis=0), contacts["force"][walls].sum(axis=0),
                               atol=1e-9)
    # no gravity, no external load in the quick scene: the totals are the contacts'
    assert np.array_equal(world.forces(), forces) and np.array_equal(world.torques(), torques)
    stress = world.stress()
    np.testing.assert_allclose(stress["sigma_plus"] + stress["sigma_minus"], stress["sigma"],
                               atol=1e-15)
    assert world.last_step.max_overlap >= world.last_step.mean_overlap >= 0.0


def test_a_scene_reads_its_values_and_takes_vectors():
    scene = cdpowder.Scene.from_toml(QUICK, {"system.gravity": [0, 0, -1e-3]})
    assert scene["system.gravity"] == [0.0, 0.0, -1e-3]
    assert scene["contact.mu"] == 0.3 and scene["run.until_blocked"] is True
    assert cdpowder.Scene.from_toml(QUICK, {"system.gravity": np.array([0.0, 0, -2])})[
        "system.gravity"] == [0.0, 0.0, -2.0]
    with pytest.raises(KeyError, match="contact.mew"):
        scene["contact.mew"]
    with pytest.raises(cdpowder.ConfigError, match=r'overrides\["contact.mu"\]'):
        cdpowder.Scene.from_toml(QUICK, {"contact.mu": -1.0})


def test_run_asks_for_an_end_and_names_a_fault():
    world = cdpowder.World.from_arrays(
        cdpowder.Scene.from_toml(QUICK), positions=[[5.0, 5.0, 1.0], [5.0, 5.0, 1.5]],
        radii=[1.0, 1.0])
    with pytest.raises(ValueError, match="until"):
        world.run(until=world.time - 1.0)
    with pytest.raises(cdpowder.RunFailed) as failed:
        world.run(steps=5)
    assert failed.value.quantity == "overlap" and failed.value.sphere in (0, 1)
    assert failed.value.step >= 1


def test_a_message_never_points_into_text_the_user_did_not_write():
    scene = cdpowder.Scene.from_keys({"deposition.spheres": 50, "system.lx": 8, "system.ly": 8})
    with pytest.raises(cdpowder.ConfigError) as error:
        cdpowder.compact(scene)
    assert str(error.value).startswith("the scene: piston.enabled: is false")
    assert "<keys>" not in str(error.value) and ":26:" not in str(error.value)


def test_every_public_name_has_a_docstring():
    """The API reference (docs/api) is generated from these docstrings."""
    missing = []
    for cls in (cdpowder.Scene, cdpowder.World, cdpowder.Result, cdpowder.StepDiagnostics):
        for name, member in vars(cls).items():
            if name.startswith("_") and name not in ("__getitem__", "__len__"):
                continue
            doc = member.__doc__ if isinstance(member, property) else getattr(member, "__doc__", "")
            # pybind11 puts the signature first; the text after it is ours
            text = [line for line in (doc or "").splitlines()
                    if line.strip() and not line.lstrip().startswith(f"{name}(")
                    and not line.lstrip().startswith("Overloaded function")]
            if not text:
                missing.append(f"{cls.__name__}.{name}")
    for name in ("deposit", "compact", "simulate", "load"):
        if not getattr(cdpowder, name).__doc__:
            missing.append(name)
    assert not missing, f"no docstring: {missing}"
