//! Every integration test, in one test binary: each file of tests/ is a
//! module here (tests/golden.rs is `golden`, and its tests are named
//! `golden::...`). One binary, not one per file, because each binary
//! compiled tests/common again and linked the whole library again: 37 of
//! them took 70 s of the fresh build on two cores (docs/perf.md, "The
//! test build (session 75)"). nextest still runs every test in a process
//! of its own.
//!
//! `cargo test --test suite golden::` runs one file's tests. A new file in
//! tests/ must be named below: tests/layers.rs fails on one that is not.

mod common;

mod bench;
mod canopy;
mod cli;
mod cli_signals;
mod cli_wind;
mod contact_cpu;
mod cover;
mod cover_dynamics;
mod cover_pose;
mod cull;
mod determinism;
mod faults;
mod frame_journal;
mod golden;
mod gpu_report;
mod grass_cpu;
mod grass_gpu;
mod host_memory;
mod layers;
mod look;
mod motion;
mod multigrid_cpu;
mod occlusion;
mod overlap;
mod ownership;
mod parser_fuzz;
mod render;
mod scene_files;
mod shader_build;
mod shaders;
mod soak;
mod terrain;
mod timing;
mod turbulence_cpu;
mod validation_matrix;
mod video;
mod viewer;
mod wind_cpu;
mod wind_gpu;
