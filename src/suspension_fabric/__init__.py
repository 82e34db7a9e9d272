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

Layout (by the workflow's stages, lowest first; a module imports only its own stage and the
stages under it, checked by tests/package/test_layout.py)
    io          -- files: resources (where the schema, LAMMPS scripts and plugin sources live),
                   schema (the one source of every default), runinfo (a finished run's record),
                   dumpio (LAMMPS boxes and dumps), stressio (the per-run stress table),
                   protocols (flow histories as data: segments, run trees)
    analysis    -- frames (bases, rotations, 6-vector storage), fabric (near contacts, <nn>;
                   MDAnalysis), fabric_reference (brute-force search), tables (per-run and seed
                   tables, steady states), stress (the stress per frame and its parts),
                   seed_statistics (the seeds as independent units)
    simulation  -- scales (time scales, output strides), lammps (the plugin, launching lmp,
                   resumable run directories, post-run checks, the public runs); imports analysis
                   for the overlap check
    models      -- gillissen_wilson (G-W and modified G-W: closure, exact integration, steady
                   states, fits, rotations), fabric_interface (what a fabric model is),
                   fabric_models and stress_relations (the plug-ins, built-in ones, integration
                   and fits; plugins loads user files), sparse_fabric (the sparse-regression
                   model), closures (<nnnn> from <nn>: linear, quadratic, hybrid), fits_file
                   (fits.json, format 2)
    study       -- config (schema validation, cross-key checks), campaign (state points),
                   validate (the command that validates a study), dataset (reference
                   datasets: load, rebuild)
    evaluation  -- model_vs_simulation (fits, predictions, errors), stress_model (the G-W stress
                   relation against the simulation), model_benchmark, stress_benchmark and
                   protocol_benchmark (held-out scores), claims and verdicts (the paper's claims
                   decided), dataset_comparison, state_map, closure_tests (the closures
                   against the measured <nnnn>)
    reporting   -- figures, map_figures, protocol_figures, closure_figures, the report pages
                   (html_tables and one module per page), protocol_report
    workflow_io -- logging helper of the Snakemake scripts
    code_version -- the rules' code versions: hashes of the code each script runs (reruns)
"""

__version__ = "0.1.0"
