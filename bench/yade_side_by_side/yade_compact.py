"""YADE's version of the paper's compaction, on a cdpowder deposit.

Run with YADE 2023.02a (Debian 12), single-threaded:

    yade -n -j1 -x bench/yade_side_by_side/yade_compact.py \
        --particles DIR/particles.csv --out result.json [--mu-roll 0.3 --mu-twist 0.3 ...]

It reads the spheres of a cdpowder particles.csv (the same deposit `cdpowder compact` starts
from), builds the experiment of Bartels et al. (cohesive spheres in a cell periodic in x and y
on a bottom wall, compacted by a piston of mass 1000 under a constant pressure, no gravity),
runs it until the piston rests and writes a small JSON file: porosity, steps, simulated time,
wall and CPU time, final piston position.

Units: R = density = F_coh = 1 (so lengths in R, forces in F_coh, masses in rho R^3, time in
t0 = sqrt(rho R^4 / F_coh), pressures in F_coh/R^2), as in cdpowder.

The contact model (YADE's soft-sphere counterpart of cdpowder's rigid contacts): CohFrictMat
spheres and walls, Ip2_CohFrictMat_CohFrictMat_CohFrictPhys with setCohesionOnNewContacts,
Law2_ScGeom6D_CohFrictPhys_CohesionMoment with incremental bending and twisting moments.
For two equal spheres of radius R (YADE's harmonic means reduce to these):

  normal        F_n = k_n (u_n - u_p), k_n = young * R = 1000 F_coh/R; u_n the overlap;
                a bonded contact holds a pull up to the normal adhesion a_n = F_coh
                (normalCohesion * R^2); beyond it the bond yields plastically at the
                constant pull F_coh (fragile = False, u_p the plastic opening) and breaks
                when the gap exceeds the cohesion range d_coh (unpMax = d_coh - F_coh/k_n,
                set on every new interaction, see BondRange). A broken bond is
                deleted; the next touch makes a new bond.
  sliding       |F_s| <= a_s + mu F_n with a_s = mu F_coh (shearCohesion * R^2), i.e.
                mu (F_n + F_coh) with F_n the net normal force (> -F_coh): cdpowder's
                threshold exactly; k_s = shear_ratio * k_n.
  rolling       |M_r| <= eta_roll R |F_n|, eta_roll = mu_roll / 2, so that the lever is
                cdpowder's r_eff = R/2; k_r = alpha_kr * k_s R^2.
  twisting      |M_t| <= eta_twist R |F_n|, eta_twist = mu_twist / 2; k_tw = alpha_ktw k_s R^2.

Where this differs from cdpowder's model (docs/lab/2026-11-25-yade-side-by-side.md):
contacts are soft (overlaps of F/k_n); YADE 2023.02a's rolling and twisting thresholds scale
with |F_n| alone, without the cohesive part F_coh that cdpowder adds (an unloaded bonded
contact rolls freely here); a bond forms only on touching (cdpowder's "graph" rule also
attracts spheres approaching within d_coh); a bond that yielded keeps its plastic opening as
its new rest length; at a wall the lever is R/2 (cdpowder: R); the contacts are damped by
Cundall's local damping (0.3) instead of being perfectly inelastic.

Cell: YADE's periodic cell, L_x x L_y x L_z with L_z above the piston. The bottom wall and the
piston are boxes much larger than the cell (InsertionSortCollider.allowBiggerThanPeriod),
the bottom fixed, the piston free along z only, of mass 1000, pushed down by the constant
force F = p L_x L_y and not damped. Everything is shifted up by the wall's thickness so that
both boxes stay inside the cell's first period.

Stop: checked every `check_every` steps, when the piston's speed has stayed below
`piston_speed` over the last `window` t0 and YADE's unbalancedForce() is below
`unbalanced_force`; or at `max_duration` (then "rested": false).
"""

import argparse
import json
import math
import resource
import sys
import time

import yade.config
from yade import O, utils
from yade.wrapper import (Bo1_Box_Aabb, Bo1_Sphere_Aabb, CohFrictMat, ForceResetter,
                          Ig2_Box_Sphere_ScGeom6D, Ig2_Sphere_Sphere_ScGeom6D,
                          InsertionSortCollider, InteractionLoop,
                          Ip2_CohFrictMat_CohFrictMat_CohFrictPhys,
                          Law2_ScGeom6D_CohFrictPhys_CohesionMoment, NewtonIntegrator,
                          PyRunner)

WALL_THICKNESS = 1.0  # [R] of the bottom wall and the piston (boxes)
WALL_EXTENT = 1000.0  # half-width of the boxes in x and y, in cell lengths
TOUCH_FACTOR = 1.0 + 1e-6  # interactions form at a gap below 2e-6 R: the deposit's touches


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--particles", required=True, help="cdpowder particles.csv (x, y, z, r)")
    p.add_argument("--out", required=True, help="JSON file to write")
    p.add_argument("--lx", type=float, default=25.0, help="cell period along x [R]")
    p.add_argument("--ly", type=float, default=25.0, help="cell period along y [R]")
    p.add_argument("--pressure", type=float, default=0.0025, help="piston pressure [F_coh/R^2]")
    p.add_argument("--piston-mass", type=float, default=1000.0, help="[rho R^3]")
    p.add_argument("--density", type=float, default=1.0, help="[rho]")
    p.add_argument("--mu", type=float, default=0.3, help="sliding friction")
    p.add_argument("--mu-roll", type=float, default=0.3, help="cdpowder's mu_roll")
    p.add_argument("--mu-twist", type=float, default=0.3, help="cdpowder's mu_twist")
    p.add_argument("--cohesion-force", type=float, default=1.0, help="F_coh [F_coh]")
    p.add_argument("--cohesion-range", type=float, default=0.01, help="d_coh [R]")
    p.add_argument("--kn", type=float, default=1000.0, help="normal stiffness [F_coh/R]")
    p.add_argument("--shear-ratio", type=float, default=0.5, help="k_s / k_n")
    p.add_argument("--alpha-kr", type=float, default=2.0, help="k_r / (k_s R^2)")
    p.add_argument("--alpha-ktw", type=float, default=2.0, help="k_tw / (k_s R^2)")
    p.add_argument("--damping", type=float, default=0.3, help="Cundall's local damping")
    p.add_argument("--dt-factor", type=float, default=0.3, help="dt / PWaveTimeStep()")
    p.add_argument("--piston-speed", type=float, default=1e-5, help="rest threshold [R/t0]")
    p.add_argument("--unbalanced-force", type=float, default=0.02, help="rest threshold")
    p.add_argument("--window", type=float, default=20.0,
                   help="the piston speed must stay below its threshold this long [t0]")
    p.add_argument("--check-every", type=int, default=100, help="steps between rest checks")
    p.add_argument("--bond-every", type=int, default=10,
                   help="steps between passes that give new bonds their range")
    p.add_argument("--max-duration", type=float, default=20000.0, help="give up after [t0]")
    p.add_argument("--timeseries", help="CSV: time, piston height and velocity per check")
    return p.parse_args(argv)


def read_particles(path):
    """(x, y, z, r) of every sphere of a cdpowder particles CSV ('#' lines are comments)."""
    with open(path) as f:
        rows = [line.strip() for line in f if line.strip() and not line.startswith("#")]
    header = rows[0].split(",")
    ix, iy, iz, ir = (header.index(k) for k in ("x", "y", "z", "r"))
    spheres = []
    for row in rows[1:]:
        v = row.split(",")
        spheres.append((float(v[ix]), float(v[iy]), float(v[iz]), float(v[ir])))
    return spheres


def add_material(a, radius):
    """One CohFrictMat for spheres and walls; see the module docstring for the mapping.
    YADE scales the stiffness by R and the adhesions by R^2, so they are divided here."""
    return O.materials.append(CohFrictMat(
        young=a.kn / radius,  # k_n = young * R for two equal spheres
        poisson=a.shear_ratio,  # k_s / k_n
        density=a.density,
        frictionAngle=math.atan(a.mu),
        isCohesive=True,
        normalCohesion=a.cohesion_force / radius**2,  # a_n = F_coh
        shearCohesion=a.mu * a.cohesion_force / radius**2,  # a_s = mu F_coh
        fragile=False,  # plastic yield at F_coh instead of a brittle break
        momentRotationLaw=True,
        etaRoll=a.mu_roll / 2.0,  # YADE's lever eta R = mu_roll r_eff, r_eff = R/2
        etaTwist=a.mu_twist / 2.0,
        alphaKr=a.alpha_kr,
        alphaKtw=a.alpha_ktw))


def build_scene(a, spheres):
    """Periodic cell, bottom wall, spheres and piston; returns (piston id, wall top z)."""
    radii = {r for _, _, _, r in spheres}
    if len(radii) != 1:
        sys.exit("yade_compact.py: the mapping of the contact law needs one radius; got "
                 f"{len(radii)}")
    mat = add_material(a, radii.pop())
    z0 = WALL_THICKNESS  # the bottom wall's top face; cdpowder's z = 0
    top = max(z + r for _, _, z, r in spheres)
    lz = z0 + top + WALL_THICKNESS + 10.0  # [R] the cell's height, above the piston
    O.periodic = True
    O.cell.hSize = ((a.lx, 0, 0), (0, a.ly, 0), (0, 0, lz))
    half = (WALL_EXTENT * a.lx, WALL_EXTENT * a.ly, WALL_THICKNESS / 2.0)
    centre_xy = (a.lx / 2.0, a.ly / 2.0)
    O.bodies.append(utils.box(center=centre_xy + (z0 - WALL_THICKNESS / 2.0,), extents=half,
                              fixed=True, material=mat))
    O.bodies.append([utils.sphere((x, y, z + z0), r, material=mat) for x, y, z, r in spheres])
    piston = O.bodies.append(utils.box(center=centre_xy + (z0 + top + WALL_THICKNESS / 2.0,),
                                       extents=half, fixed=False, material=mat))
    state = O.bodies[piston].state
    state.mass = a.piston_mass
    state.blockedDOFs = "xyXYZ"  # moves along z only
    state.isDamped = False  # a free heavy piston, as in the paper
    O.forces.setPermF(piston, (0, 0, -a.pressure * a.lx * a.ly))
    return piston, z0


def set_engines(a):
    law = Law2_ScGeom6D_CohFrictPhys_CohesionMoment(useIncrementalForm=True,
                                                     always_use_moment_law=True)
    O.engines = [
        ForceResetter(),
        # The boxes span many periods in x and y. The collider's first search runs along
        # sortAxis, from each body's lower to its upper bound with both wrapped into the
        # cell: along x or y a box's wrapped bounds cover only part of the cell and spheres
        # resting on the wall are missed (they then pass through it); along z they do not.
        InsertionSortCollider([Bo1_Sphere_Aabb(aabbEnlargeFactor=TOUCH_FACTOR), Bo1_Box_Aabb()],
                              allowBiggerThanPeriod=True, sortAxis=2),
        InteractionLoop(
            [Ig2_Sphere_Sphere_ScGeom6D(interactionDetectionFactor=TOUCH_FACTOR),
             Ig2_Box_Sphere_ScGeom6D(interactionDetectionFactor=TOUCH_FACTOR)],
            [Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionOnNewContacts=True)],
            [law]),
        NewtonIntegrator(damping=a.damping),
        PyRunner(command="set_bond_range()", iterPeriod=a.bond_every, initRun=True),
        PyRunner(command="check_rest()", iterPeriod=a.check_every),
    ]
    O.dt = a.dt_factor * utils.PWaveTimeStep()


class BondRange:
    """Gives new bonds the cohesion range. YADE 2023.02a creates every bond with unpMax = 0,
    which breaks it as soon as it yields (at the gap F_coh/k_n = 1e-3 R) and offers no
    material or functor setting for it, so a pass over the interactions every `bond_every`
    steps sets unpMax = d_coh - F_coh/k_n on those that still have 0. A bond that yields
    before its pass breaks at 1e-3 R instead of d_coh. Measured on a 150-sphere deposit at
    (0.3, 0.3): passes every step and every 10 steps give the same run to the last digit
    (porosity 0.68300); every 50 and 100 steps 0.68514 and 0.68060, no passes 0.67870. The
    default is 10 steps (0.1 t0). The passes run in Python, outside YADE's engines, and take
    about a tenth of the CPU time (10 of 100 s at paper size); their time is part of
    `cpu_seconds` and is also reported on its own."""

    def __init__(self, unp_max):
        self.unp_max = unp_max  # [R] plastic opening at which a bond breaks
        self.cpu_seconds = 0.0

    def __call__(self):
        start = time.process_time()
        for i in O.interactions:
            if i.phys.unpMax == 0.0:
                i.phys.unpMax = self.unp_max
        self.cpu_seconds += time.process_time() - start


set_bond_range = None  # the BondRange of this run, called by a PyRunner


class RestCheck:
    """Called every `check_every` steps: ends the run once the piston's speed has been below
    its threshold at every check over the last `window` t0 and the force balance holds, or
    at `max_duration`. Keeps the timeseries rows when asked for."""

    def __init__(self, a, piston, z0):
        self.a = a
        self.piston = piston
        self.z0 = z0
        self.still_since = None  # [t0] the first check of the current stretch below threshold
        self.rested = False
        self.rows = []  # (time [t0], piston height [R], piston velocity [R/t0], unbalanced)

    def __call__(self):
        state = O.bodies[self.piston].state
        speed = abs(state.vel[2])
        if speed >= self.a.piston_speed:
            self.still_since = None
        elif self.still_since is None:
            self.still_since = O.time
        unbalanced = float("nan")
        if self.a.timeseries or self._window_full():
            unbalanced = utils.unbalancedForce()
        if self.a.timeseries:
            height = state.pos[2] - WALL_THICKNESS / 2.0 - self.z0
            self.rows.append((O.time, height, state.vel[2], unbalanced))
        if self._window_full() and unbalanced < self.a.unbalanced_force:
            self.rested = True
            O.pause()
        if O.time >= self.a.max_duration:
            O.pause()

    def _window_full(self):
        return self.still_since is not None and O.time - self.still_since >= self.a.window

    def write_timeseries(self):
        with open(self.a.timeseries, "w") as f:
            f.write("time,piston_height,piston_velocity,unbalanced_force\n")
            for row in self.rows:
                f.write(",".join(repr(v) for v in row) + "\n")


check_rest = None  # the RestCheck of this run, called by a PyRunner


def porosity(a, spheres, piston, z0):
    height = O.bodies[piston].state.pos[2] - WALL_THICKNESS / 2.0 - z0  # [R] face to face
    grains = sum(4.0 / 3.0 * math.pi * r**3 for _, _, _, r in spheres)
    return 1.0 - grains / (a.lx * a.ly * height), height


def escaped(piston, z0):
    """Spheres whose centre is not between the wall and the piston (0 in a sound run)."""
    face = O.bodies[piston].state.pos[2] - WALL_THICKNESS / 2.0
    return sum(1 for b in O.bodies
               if b.id != piston and b.dynamic and not z0 < b.state.pos[2] < face)


def main(argv):
    global set_bond_range, check_rest
    a = parse_args(argv)
    spheres = read_particles(a.particles)
    set_bond_range = BondRange(a.cohesion_range - a.cohesion_force / a.kn)
    piston, z0 = build_scene(a, spheres)
    check_rest = RestCheck(a, piston, z0)
    set_engines(a)
    e0, h0 = porosity(a, spheres, piston, z0)

    wall0, cpu0 = time.perf_counter(), time.process_time()
    O.run()
    O.wait()
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0

    e, h = porosity(a, spheres, piston, z0)
    usage = resource.getrusage(resource.RUSAGE_SELF)
    result = {
        "program": "yade " + yade.config.version,
        "spheres": len(spheres),
        "initial_porosity": e0,
        "initial_piston_height": h0,
        "porosity": e,
        "piston_height": h,  # [R] from the bottom wall's face to the piston's face
        "piston_velocity": O.bodies[piston].state.vel[2],  # [R/t0]
        "unbalanced_force": utils.unbalancedForce(),
        "escaped_spheres": escaped(piston, z0),
        "rested": check_rest.rested,
        "steps": O.iter,
        "time": O.time,  # [t0] simulated
        "dt": O.dt,  # [t0]
        "interactions": O.interactions.countReal(),
        "wall_seconds": wall,  # the run loop only
        "cpu_seconds": cpu,
        "bond_pass_cpu_seconds": set_bond_range.cpu_seconds,  # part of cpu_seconds
        "process_cpu_seconds": usage.ru_utime + usage.ru_stime,  # setup and start-up too
        "parameters": vars(a),
    }
    with open(a.out, "w") as f:
        json.dump(result, f, indent=2)
    if a.timeseries:
        check_rest.write_timeseries()
    print(json.dumps({k: result[k] for k in ("porosity", "steps", "time", "wall_seconds",
                                             "cpu_seconds", "rested")}))


main(sys.argv[1:])
