"""Flow-induced anisotropy of dense non-Brownian suspensions.

Reproduces and extends Acharya & Mari, "Modelling the evolution of flow-induced
anisotropy of concentrated suspensions": LAMMPS discrete-element simulations of
startup shear and shear rotation, near-contact fabric tensors from the
trajectories, and the Gillissen-Wilson (G-W) fabric model with its modification.

Conventions (the single source of truth; every module follows them)
--------------------------------------------------------------------
Units
    Strain rate gammadot = 1, small-particle diameter d = 1, mass rho d^3 with
    rho = 1 for particles and fluid. Time therefore equals strain.

Paper frame
    e1 flow, e2 gradient, e3 = e1 x e2 vorticity. Simple shear is
    L = gammadot e1 e2 (L_ij = du_i/dx_j, so L_12 = gammadot).

Simulation frame (LAMMPS triclinic box)
    z is the gradient direction for the whole run. A shear with flow direction
    f = (cos t, sin t, 0) is ``fix deform ... xz erate cos(t) yz erate sin(t)``.
    Startup uses t = 0, where e1 = x, e2 = z, e3 = -y.

Shear rotation by theta
    Flow e1 and vorticity e3 turn by theta about e2, right-handed:
    e1' = cos(theta) e1 - sin(theta) e3,  e3' = sin(theta) e1 + cos(theta) e3.
    In the simulation frame that is the flow direction f = (cos theta, sin theta, 0).
    After a rotation every reported component is in the rotated frame
    (e1', e2, e3'): <nn>' = R <nn> R^T with rows e1', e2, e3' of R, so just after it
    <nn>'_12 = cos(theta) <nn>_12 - sin(theta) <nn>_23 and
    <nn>'_23 = sin(theta) <nn>_12 + cos(theta) <nn>_23 (<nn>_23 = 0 in a steady state).

Fabric
    A near contact is a pair with surface gap h < eps * min(d_i, d_j), eps = 0.01.
    <nn>_ij = (1/N) sum over near-contact pairs (each once) of n_i n_j, with N the
    number of particles; hence Tr<nn> = Z/2, Z the near-contact coordination.

Modules
    frames       -- paper/simulation/rotated frame bases and tensor rotations
    model        -- G-W and modified G-W models: closure, rhs, exact integration,
                    steady states, fits, shear-rotation predictions
    resources    -- where the schema, the LAMMPS scripts and the plugin sources live
    schema       -- the study schema and its defaults (the one source of every default)
    lammps       -- the project's LAMMPS plugin (build, load) and the runners of the
                    workflow/lammps scripts (pack, startup shear, shear rotation):
                    plugin, process (launch, watch), checks, rundir (partial runs,
                    resume, publishing), runner (the public runs)
    dumpio       -- LAMMPS triclinic boxes and dump files (writer, reader, header checks)
    stressio     -- the per-run stress table
    fabric       -- near-contact detection and per-frame fabric (MDAnalysis)
    fabric_reference -- brute-force O(N^2) near-contact search: fallback of the overlap
                    check for small boxes, reference of the tests
    runinfo      -- a finished run's time step, rate, first step, flow angle and eta_f (from
                    its completion marker)
    tables       -- per-run fabric tables, seed aggregates, steady states (of any per-frame table)
    stress       -- the stress per frame: symmetric contact, lubrication, kinetic, solvent and
                    Einstein parts in the paper frame of the current shear, eta_r, N1, N2, Pi
    stress_model -- the G-W stress relation: fits per fabric source, predictions, errors,
                    the viscosity deficit after a rotation per seed (minimum, recovery as description)
    model_vs_simulation -- models versus simulation: fits to the simulated steady
                    state, predictions at the simulated strains and angles, errors
    seed_statistics -- the seeds as independent units: t-intervals, the three-way decision
                    rule, seeds needed, jackknife and seed bootstrap
    claims       -- the shear-rotation claims decided per seed: each seed's own fits and
                    predictions under a choice, linear statistics, verdicts, choices table
    verdicts     -- the steady-state claims; recovery, rms and overshoot tables (description)
    figures      -- the paper's Fig. 1 and Fig. 2; the stress figures 3 and 4; Fig. 5 (claims)
    report_tables -- fits, steady state, error summary, verdicts and stress as HTML tables for the report
    dataset      -- reference datasets: a finished study's tables, committed, rebuilt without simulating
    config       -- study configuration: schema validation, cross-key checks
    workflow_io  -- logging helper of the Snakemake scripts
"""

__version__ = "0.1.0"
