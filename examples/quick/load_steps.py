"""A sweep's Python protocol (docs/sweeps.md, "A Python protocol"): a loading path in steps.

Each point's deposit is compacted at the scene's pressure p until it blocks, then the same
packing at 2p and at 4p. The last stage writes the run's files into `out`, so the sweep's
tables hold E and the stresses at 4p; the porosity after each step is returned and kept in
protocol.json. Run it with examples/quick/load_steps_sweep.toml:
    cdpowder sweep examples/quick/load_steps_sweep.toml --out runs/load_steps
"""
import cdpowder

FACTORS = (1, 2, 4)


def load_steps(scene, out):
    """E after compactions at p, 2p and 4p of one packing; the last one written to `out`."""
    p = scene["piston.pressure"]
    world = None  # the first compaction makes the scene's deposit
    porosity = {}
    for factor in FACTORS:
        stage = scene.with_overrides({"piston.pressure": p * factor})
        result = cdpowder.compact(stage, world=world, out=out if factor == FACTORS[-1] else None)
        world = result.world
        porosity[f"{factor}p"] = result.porosity
    return {"porosity": porosity}
