//! The integration tests, one module per file: one test binary, so that the crate and its generic
//! dual-number code are linked and instantiated once instead of once per file. `cargo test NAME`
//! selects tests by name; `cargo test --test it MODULE::` runs one file's tests (e.g.
//! `cargo test --test it tangents::`).

// Helpers shared by the modules.
mod biaxial_fit;
mod binary;
mod common;
mod deadline;
mod scratch;

mod activation_in_time;
mod activation_laws;
mod active_curves;
mod active_strain_map;
mod approach_column;
mod approach_registry;
mod approaches;
mod bounded_loops;
mod cauchy_stress;
mod check_passes_run;
mod cli_end_to_end;
mod cli_fit;
mod cli_runs;
mod cli_scene;
mod cli_stability;
mod closed_form;
mod cylinder_muscle;
mod cylinder_points;
mod cylinder_regions;
mod datapackage;
mod energy_battery;
mod extremes;
mod fem_clamped;
mod fem_condensation;
mod fem_element;
mod fem_fenics_reference;
mod fem_geometry;
mod fem_limits;
mod fem_nearly_incompressible;
mod fem_newton;
mod fem_output;
mod fem_relaxation;
mod fem_sliding;
mod fit_errors;
mod fit_extremes;
mod fit_jacobian;
mod fit_paper;
mod fit_recovery;
mod formula_energy;
mod formula_fit;
mod four_c_blocks;
mod four_c_passive;
mod golden_run;
mod input_caps;
mod law_representation;
mod library_run;
mod nearly_incompressible;
mod paper_closed_forms;
mod proptest_responses;
mod report_follows_the_scene;
mod scene_fuzz;
mod scene_incompressibility;
mod scene_specs;
mod scene_tradeoff;
mod scratch_dirs;
mod shear_biaxial;
mod shipped_scenes;
mod stability;
mod study_names;
mod tabulated_law;
mod tangents;
mod tradeoff_machinery;
mod truthful_reports;
mod uniaxial;
mod volumetric_outputs;
