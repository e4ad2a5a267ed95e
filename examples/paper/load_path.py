"""A sweep's Python protocol (docs/sweeps.md, "A Python protocol"): one packing's loading path.

The deposit is compacted at p/4 until it blocks; the same packing is then loaded in doublings
to 32p, each stage until it blocks again, and unloaded back to p/4. A fresh compaction at each pressure
is the `piston.pressure` points of examples/paper/additivity_sweep.toml (p/4, p, 4p) and
Table 1 (p), so E(p) along the path can be set beside E(p) of a packing made at p: is the
porosity a function of the load, or of how the packing was first compacted? The last stage
(the unloading) writes the run's files; protocol.json keeps E, σzz⁺/p and the piston's height
after every stage.
    cdpowder sweep examples/paper/load_path_sweep.toml --out results/paper/load_path --jobs 2
"""
import cdpowder

# the stages' pressures over the scene's p; the last is the unloading
FACTORS = (0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 0.25)


def load_path(scene, out):
    """E, σzz⁺/p and the piston's height after each stage of one packing's loading path."""
    p = scene["piston.pressure"]
    world = None  # the first compaction makes the scene's deposit
    stages = []
    for k, factor in enumerate(FACTORS):
        stage = scene.with_overrides({"piston.pressure": p * factor})
        last = k == len(FACTORS) - 1
        result = cdpowder.compact(stage, world=world, out=out if last else None)
        world = result.world
        stress = world.stress()
        stages.append({"pressure_over_p": factor, "porosity": result.porosity,
                       "sigma_zz_plus_over_applied": stress["sigma_plus"][2][2] / (p * factor),
                       "piston_height": world.piston_height, "time": world.time,
                       "blocked": bool(result.summary["run"]["blocked"])})
    return {"stages": stages}
