// The one source of the Rust/GLSL interface: every push-constant block the
// kernels and pipelines read, the records of the storage buffers both sides
// write or read, and the constants both sides use. The library
// makes `#[repr(C)]` structs and constants of it (src/interface/mod.rs);
// build.rs writes the GLSL (`interface.glsl`, which shaders include) and a
// compile-time check that each Rust field lies where std430 puts it
// (src/interface_build.rs). Field types: f32, u32, i32, `[T; 2..4]` of
// those (vectors; a vec3 is aligned to 16 bytes and a scalar may follow it
// in the same 16), `Mat4Columns` (mat4), arrays, structs defined above.
// A struct named `...Push` must fit 128 bytes. Fields named `_pad*` only
// fill the bytes std430 leaves between members.
gpu_interface! {
    /// Invocations per workgroup of every wind kernel (glsl/wind/).
    pub const WIND_GROUP: u32 = 64;
    /// Invocations of the one workgroup that runs a multigrid V-cycle's
    /// coarse levels (glsl/wind/mg_tail.glsl): what every Vulkan device
    /// must offer.
    pub const MG_TAIL_GROUP: u32 = 128;
    /// Red-black Gauss-Seidel sweeps before restricting and after
    /// prolonging (src/model/multigrid.rs).
    pub const MG_PRE_SMOOTH: u32 = 2;
    pub const MG_POST_SMOOTH: u32 = 2;
    /// Levels a multigrid hierarchy can have: each halves at least one
    /// axis, and a wind grid has fewer than 2^32 cells.
    pub const MG_MAX_LEVELS: usize = 40;
    /// A fine level's fused red-black sweep (glsl/wind/mg_sweep.comp): its
    /// invocations, and the cells of the tile one workgroup sweeps (x, y,
    /// z; fewer along an axis the level is shorter than). The workgroup
    /// keeps the red cells of its tile and of one cell around it, so both
    /// colours' half-sweeps run in one dispatch: 9 x 22 x 18 floats,
    /// 13.9 KiB.
    pub const MG_SWEEP_GROUP: u32 = 256;
    pub const MG_SWEEP_TILE_X: u32 = 16;
    pub const MG_SWEEP_TILE_Y: u32 = 20;
    pub const MG_SWEEP_TILE_Z: u32 = 16;
    pub const MG_SWEEP_FLOATS: u32 = 3564;
    /// Floats of the tail kernel's shared array (glsl/wind/mg_tail.glsl)
    /// beside its level table (40 `MgLevel`s, 40 offsets and two counts:
    /// 2,088 bytes): in 16 KiB, what every device offers a workgroup
    /// (mg_tail.comp), and in 48 KiB (mg_tail_large.comp).
    pub const MG_TAIL_FLOATS: u32 = 3574;
    pub const MG_TAIL_FLOATS_LARGE: u32 = 11766;
    /// Invocations of the one workgroup that chooses a pressure solve's
    /// start and checks its residual after each V-cycle
    /// (glsl/wind/mg_start.comp, mg_check.comp).
    pub const MG_CHECK_GROUP: u32 = 256;
    /// Entries of the pressure solves' histogram of V-cycles per step:
    /// 0 to `scene::check::MAX_V_CYCLES` (100), padded to 16 bytes.
    pub const MG_HISTOGRAM: usize = 104;
    /// Invocations per workgroup of the grass step and collider-binning
    /// kernels (glsl/grass/).
    pub const GRASS_GROUP: u32 = 64;
    /// Iterations of the far field's quasi-static solve at most (the
    /// cover's pose: glsl/grass/quasi_static.glsl and
    /// `quasi_static::FAR_ITERATIONS`).
    pub const QUASI_STATIC_ITERATIONS: usize = 12;
    /// The quasi-static solve's pseudo-time term: its first (and largest)
    /// weight, in units of the still-air stiffness, and the least it
    /// falls each iteration (src/model/quasi_static.rs says why these).
    pub const QS_START_RELAXATION: f32 = 10.0;
    pub const QS_RELAXATION_SHRINK: f32 = 0.6;
    /// The largest change of an angle in one iteration (rad).
    pub const QS_MAX_TURN: f32 = 0.25;
    /// Central-difference step of the Jacobian (rad).
    pub const QS_DIFFERENCE: f32 = 1e-3;
    /// Done when no angle changes by more than this (rad).
    pub const QS_TOLERANCE: f32 = 1e-6;
    /// Invocations per workgroup of the cover's tile kernel
    /// (glsl/cover/tiles.comp): one blade each.
    pub const COVER_GROUP: u32 = 64;
    /// The band (m) inside `simulate_radius` over which a kept cover
    /// blade's pressing fades out (`cover::PRESS_FADE_M`): beyond the
    /// radius no collider presses the far field.
    pub const COVER_PRESS_FADE_M: f32 = 4.0;
    /// The central differences a root's ground normal is taken over (m)
    /// (`terrain::NORMAL_STEP_M`).
    pub const TERRAIN_NORMAL_STEP_M: f32 = 0.01;
    /// The cover's fit of a blade's rest shape to the ground
    /// (`cover::fitted`, glsl/cover/tiles.comp): the points of its curve
    /// tested against the ground's height (at t = 1/8, 2/8 .. 1), ...
    pub const COVER_FIT_SAMPLES: u32 = 8;
    /// ... each kept this far above it per metre from the root
    /// (`blade::FIT_ROOM`: the room a patch's fitted blade keeps inside
    /// contact's region, and every rest shape at rest, about half a
    /// degree of lean; the cover's fit keeps its control points so far
    /// over the tangent plane, so that contact's region holds them) ...
    pub const FIT_ROOM: f32 = 0.01;
    /// ... turning the blade about the vertical through its root by
    /// multiples of pi / COVER_FIT_TURNS each way, then, where no turn
    /// fits, shrinking its lean in COVER_FIT_SHRINKS steps.
    pub const COVER_FIT_TURNS: u32 = 32;
    pub const COVER_FIT_SHRINKS: u32 = 16;
    /// Halvings of the search for how far toward rest the ground holds a
    /// far blade the wind's balance would press into it
    /// (`cover::held_above_ground`): to 1/256 of its angles.
    pub const COVER_HOLD_HALVINGS: u32 = 8;
    /// Blades per workgroup of the cull pass's flag and compaction kernels:
    /// one blade per invocation (glsl/cull/).
    pub const CULL_GROUP: u32 = 256;
    /// Texels a side of the depth pyramid kernels' 2D workgroups.
    pub const PYRAMID_TILE: u32 = 8;
    /// Words before the blades of a batch's list of touching blades: the
    /// indirect dispatch's three workgroup counts, then the count.
    pub const TOUCHING_HEADER: u32 = 4;
    /// Lattice coordinates within this of a whole number count as on it
    /// when MacCormack's clamp picks its eight samples
    /// (`model::wind::RANGE_SNAP`).
    pub const WIND_RANGE_SNAP: f32 = 1e-3;
    /// Waypoints a moving source or collider's path may have.
    pub const MAX_PATH_POINTS: usize = 8;
    /// Colliders a scene may have (the collider bins hold one bit each).
    pub const MAX_COLLIDERS: usize = 128;
    /// The wind's face kinds (`model::wind::FaceKind`), as the face-kind
    /// buffer holds them: a free face, moved by the solver.
    pub const FACE_FREE: u32 = 0;
    /// A wall: the face holds zero.
    pub const FACE_WALL: u32 = 1;
    /// On an inflow's entry side: the face holds the inflow's velocity.
    pub const FACE_INFLOW: u32 = 2;
    /// Between two cells under the ground: the free-slip ghost value of
    /// the air above (glsl/wind/under_ground.comp).
    pub const FACE_BURIED: u32 = 3;

    /// The fragment stages' data view for `meadow render --light-waves`
    /// (src/report/light_waves.rs), beside `ViewMode`'s pictures (0
    /// shaded, 1 LOD, 2 motion; glsl/common/frame.glsl): a blade writes
    /// its displacement in red (over `DISPLACEMENT_FULL_SCALE`) and 1 in
    /// blue, everything else black, unlit.
    pub const VIEW_DISPLACEMENT: u32 = 3;
    /// The displacement (rad) the data view's red channel reads 1 at.
    pub const DISPLACEMENT_FULL_SCALE: f32 = 1.5707964;

    /// The grass dynamics' motions, in the order of every per-motion vec4
    /// (src/model/grass.rs, glsl/common/grass_blade.glsl): swinging ...
    pub const SWING: usize = 0;
    /// ... bending of the rising edges (all edges of a blade that never
    /// falls) ...
    pub const BEND_A: usize = 1;
    /// ... bending of a drooping blade's falling edges (unused otherwise) ...
    pub const BEND_B: usize = 2;
    /// ... and twisting.
    pub const TWIST: usize = 3;
    /// The largest bending or swinging angle (rad). The restoring force
    /// fades as cos(theta / 2), so only a guard keeps a blade from folding
    /// through itself under absurd wind; at the limit the motion stops.
    pub const MAX_ANGLE: f32 = 2.5;
    /// Wind beyond this speed (m/s) is treated as this speed: a guard
    /// against a runaway field, far above any documented setting.
    pub const MAX_WIND_SPEED: f32 = 100.0;
    /// Touch (src/model/contact.rs, glsl/grass/contact.glsl): projections
    /// per substep, each pushing the deepest point out.
    pub const CONTACT_ITERATIONS: usize = 8;
    /// Metres beyond the surface a projection pushes a point, so that a
    /// resting contact settles just outside instead of flickering on it.
    pub const CONTACT_SLOP: f32 = 0.002;
    /// The largest change of one angle in one projection (rad): where the
    /// contact is nearly perpendicular to every motion (a point straight
    /// under a ball's centre), the linear step would be huge.
    pub const MAX_CORRECTION: f32 = 0.5;
    /// The time a touching blade takes to become fully pressed (s): a
    /// ramp, so that the pressed pose's change is never a jump.
    pub const PRESS_RISE_TIME: f32 = 0.05;
    /// How much a fully pressed blade's swing and bend restoring forces
    /// are weakened (1: none left).
    pub const PRESS_SOFTENING: f32 = 0.9;
    /// A root edge that lies within this of flat (rad) keeps eq. 12's
    /// shares when pressed: there is nothing to lay down.
    pub const MIN_FLAT_TURN: f32 = 0.05;

    /// One control point of a blade as the render pipeline reads it: four
    /// per blade, one patch; the grass step writes them
    /// (glsl/common/blade_vertex.glsl).
    pub struct BladeVertex {
        /// The control point in world space (m).
        pub position: [f32; 3],
        /// The blade's random value in [0, 1) (colour variation).
        pub blade_rand: f32,
        /// The half-width vector at this point: E_w times the half width (m).
        pub half_width: [f32; 3],
        /// Angular displacement from rest (rad; the motion view).
        pub displacement: f32,
    }

    /// One blade as the grass kernel reads it (glsl/common/grass_blade.glsl;
    /// src/model/grass.rs derives it). Everything derivable from the rest
    /// shape and the physics is computed once. Per-motion vec4s are in the
    /// order swing, bend A, bend B, twist.
    pub struct GrassBlade {
        /// The rest control points P_0 to P_3, each with what the blade
        /// keeps beside it: the blade's random value (colour), the x of
        /// the ground's upward unit normal at the root, ground contact's c
        /// (`Blade::ground_curvature`), the normal's z (its y follows).
        pub rest_root: [f32; 3],
        pub blade_rand: f32,
        pub rest_1: [f32; 3],
        pub ground_normal_x: f32,
        pub rest_2: [f32; 3],
        pub ground_curvature: f32,
        pub rest_tip: [f32; 3],
        pub ground_normal_z: f32,
        /// Rest E_w (unit, horizontal).
        pub width_dir: [f32; 3],
        /// Half width (m).
        pub half_width: f32,
        /// k_i of edges 0, 1, 2 (root to tip).
        pub stiffness: [f32; 3],
        /// The first edge of bending group B (3: one group).
        pub group_b_edge: u32,
        /// sigma S per motion (S: the area the motion exposes).
        pub drag: [f32; 4],
        /// I = m r^2 per motion.
        pub inertia: [f32; 4],
        /// c per motion.
        pub damping: [f32; 4],
    }

    /// Angle and angular velocity of each motion.
    pub struct GrassState {
        /// theta per motion (rad).
        pub angle: [f32; 4],
        /// omega per motion (rad/s).
        pub velocity: [f32; 4],
    }

    /// A blade's pressed state as the grass step keeps it
    /// (glsl/grass/contact.glsl; `Press::next` in src/model/contact.rs): the
    /// pressed state its last step used (and its pose shows) and whether
    /// that step touched a collider.
    pub struct Press {
        pub pressed: f32,
        /// 1 if the step touched a collider, else 0.
        pub touched: f32,
    }

    /// One collider as the binning and wind kernels read it
    /// (glsl/common/collider.glsl; `Collider` in src/model/collider.rs).
    pub struct GpuCollider {
        /// Position without a path (m).
        pub position: [f32; 3],
        pub radius: f32,
        /// 1: an upright capsule; 0: a sphere.
        pub capsule: u32,
        /// A capsule's height (m).
        pub height: f32,
        /// Points of its path (0: none), and its speed along it (m/s).
        pub path_points: u32,
        pub path_speed: f32,
        /// 1 when the path is closed.
        pub closed: u32,
        /// The time it sets off (s).
        pub sets_off: f32,
        pub _pad0: u32,
        pub _pad1: u32,
        /// Waypoints (m): xyz, each in 16 bytes as std430 lays out an
        /// array of vec3 (w unused).
        pub path: [[f32; 4]; MAX_PATH_POINTS],
    }

    /// A collider at one instant, as the binning kernel writes it for the
    /// grass step (`ColliderState` in src/model/collider.rs): the segment a..b
    /// swept by the radius, and the velocity of its centre.
    pub struct GpuColliderState {
        pub a: [f32; 3],
        pub radius: f32,
        pub b: [f32; 3],
        pub _pad0: u32,
        /// m/s.
        pub velocity: [f32; 3],
        pub _pad1: u32,
    }

    /// One wind source as the wind kernels read it
    /// (glsl/wind/wind_kernel.glsl; `WindSource` in src/model/wind/drive.rs).
    pub struct GpuWindSource {
        /// Position at t = 0 and radius (m).
        pub position: [f32; 3],
        pub radius: f32,
        /// Unit direction at t = 0, and strength (m/s^2).
        pub direction: [f32; 3],
        pub strength: f32,
        /// The gust's phases (rad), amplitude and frequency (Hz).
        pub gust_phases: [f32; 3],
        pub gust_amplitude: f32,
        pub gust_frequency: f32,
        /// Rotation speed (rad/s).
        pub rotation_speed: f32,
        /// Speed along the path (m/s) and its points.
        pub path_speed: f32,
        /// Off after this time (s; infinite: never).
        pub off_after: f32,
        pub path_points: u32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
        /// Waypoints of the closed path (m): xyz, each in 16 bytes as
        /// std430 lays out an array of vec3 (w unused).
        pub path: [[f32; 4]; MAX_PATH_POINTS],
    }

    /// One Fourier mode of the turbulence as glsl/common/turbulence.glsl
    /// reads it (src/model/turbulence.rs), written before each step: the
    /// grid's for glsl/wind/turbulence.comp, those finer than the grid for
    /// the grass step.
    pub struct TurbulenceMode {
        /// Wavenumber k (rad/m).
        pub wavenumber: [f32; 3],
        /// The mode's phase at the step's end, taken at the grid's minimum
        /// corner (rad, in [0, 2 pi)).
        pub phase: f32,
        /// What the mode adds to a face of each axis at phase 0 (m/s); a
        /// mode finer than the grid, its velocity at phase 0.
        pub amplitude: [f32; 3],
        /// Bit a: the mode is paired with its mirror images across the
        /// grid's two sides across axis a (`model::turbulence::at`).
        pub mirrored: u32,
    }

    /// One multigrid level as the kernels read it (glsl/wind/multigrid.glsl;
    /// src/model/multigrid.rs).
    pub struct MgLevel {
        pub cells: [u32; 3],
        /// The offset of this level in the coarse arrays.
        pub coarse_offset: u32,
        /// Fine cells per coarse cell towards the next level.
        pub ratio: [u32; 3],
        pub _pad0: u32,
        /// The offset of each axis's face conductances.
        pub conductance: [u32; 3],
        pub _pad1: u32,
    }

    /// The wind grid as every wind and grass kernel sees it (staggered: the
    /// velocity's component a lives on the cells' a-faces;
    /// glsl/common/wind_grid.glsl).
    pub struct WindGridParams {
        /// Cells along x, y and z.
        pub cells: [u32; 3],
        /// Faces of all three components: the length of one velocity copy.
        pub faces: u32,
        /// World position of the grid's minimum corner (m).
        pub origin: [f32; 3],
        pub _pad0: u32,
        /// Cell size along each axis (m).
        pub cell_size: [f32; 3],
        pub _pad1: f32,
    }

    /// Push constants of every wind kernel (glsl/wind/wind_kernel.glsl).
    pub struct WindPush {
        pub grid: WindGridParams,
        /// Simulation time at the step's start (s).
        pub time: f32,
        /// The step dt (s).
        pub dt: f32,
        /// The canopy drag coefficient C_d (0: one-way coupling, no drag).
        pub canopy_drag: f32,
        /// Frontal area per volume (1/m) that one canopy count on each side
        /// of a face adds to it.
        pub area_per_count: f32,
        /// Wind sources in the sources buffer.
        pub source_count: u32,
        /// Jacobi: the pressure half this iteration reads (0 or 1).
        pub pressure_read: u32,
        /// The pressure half holding the solve's result.
        pub pressure_result: u32,
        /// Multigrid: the V-cycles stop once the rms residual is at most
        /// this share of the right-hand side's (`Multigrid::solve`).
        pub pressure_tolerance: f32,
        /// The inflow's mean speed (m/s; 0: no inflow).
        pub inflow_speed: f32,
        /// The inflow gusts' relative amplitude.
        pub gust_amplitude: f32,
        /// The inflow gusts' frequency (Hz).
        pub gust_frequency: f32,
        /// Where the inflow blows towards (radians; 0 along +x, pi/2
        /// along +z).
        pub inflow_heading: f32,
        /// The phases of the gusts' three sines.
        pub gust_phases: [f32; 3],
        /// Colliders pushing the air (the forces kernel).
        pub collider_count: u32,
        /// Multigrid: the level a kernel works on.
        pub mg_level: u32,
        /// Multigrid: the colour a half-sweep updates (mg_smooth.comp), or
        /// which copy a fused sweep reads (mg_sweep.comp: 1 the sweep
        /// scratch, writing the level's pressure; 0 the reverse).
        pub mg_sweep: u32,
        /// Multigrid: Gauss-Seidel sweeps on the coarsest level.
        pub coarsest_sweeps: u32,
        /// Multigrid: coarse cells of all levels (where the right-hand
        /// sides start in the coarse buffer).
        pub coarse_cells: u32,
    }

    /// The head of the multigrid's solve buffer (glsl/wind/mg_solve.glsl;
    /// `Multigrid::solve`), followed by the V-cycle's indirect dispatches:
    /// `dispatches` live ones (zeroed once the residual is small enough),
    /// then the same as made, which each step's start copies.
    pub struct MgSolve {
        /// V-cycles this step has run.
        pub v_cycles: u32,
        /// Where this step's solve started: 0 zero, 1 the last pressure,
        /// 2 the last two carried on (`multigrid::Start`).
        pub start: u32,
        /// Sum over level 0's cells of b^2.
        pub b_squares: f32,
        /// The rms residual over b's after the last V-cycle (or at the start).
        pub share_left: f32,
        /// 1 once the residual is at most the tolerance.
        pub converged: u32,
        /// Steps solved before this one (in `histogram`).
        pub steps: u32,
        /// The V-cycle's indirect dispatches (written once, at creation).
        pub dispatches: u32,
        pub _pad0: u32,
        /// Steps before this one by their V-cycles.
        pub histogram: [u32; MG_HISTOGRAM],
    }

    /// Push constants of the wind window's shift (glsl/wind/shift.comp;
    /// src/model/wind/window.rs): the wind kernels' set, its own push.
    pub struct WindShiftPush {
        /// The grid before the shift (only its cells and faces are read).
        pub grid: WindGridParams,
        /// Whole cells the window moves by along x and z.
        pub shift: [i32; 2],
        /// 0: the moved air into copy B and the moved canopy into the
        /// divergence buffer; 1: both copied back, the pressure cleared.
        pub phase: u32,
        pub _pad0: u32,
        /// What a face with no air to take holds: the inflow's mean
        /// velocity (m/s).
        pub fill: [f32; 3],
        pub _pad1: f32,
    }

    /// Push constants of the grass kernels (glsl/grass/step.glsl).
    pub struct GrassPush {
        pub grid: WindGridParams,
        /// Blades this dispatch steps.
        pub blade_count: u32,
        /// Substeps per step.
        pub substeps: u32,
        /// Where (in floats) the wind velocity copy to sample starts.
        pub wind_offset: u32,
        /// 1 to lay the canopy's frontal area (two-way coupling).
        pub lay_canopy: u32,
        /// The simulation step dt (s).
        pub dt: f32,
        /// The substep h = dt / substeps (s).
        pub substep: f32,
        /// m^2 per count of the canopy buffer.
        pub canopy_unit: f32,
        /// Time at the step's end (s): where the colliders are.
        pub end_time: f32,
        /// The pressed state's decay per step.
        pub press_decay: f32,
        /// Colliders (src/model/contact.rs), taken from the bins at each step.
        pub collider_count: u32,
        /// 1 where each blade has a pressed state (made with colliders).
        pub pressed_states: u32,
        /// The collider bins: cells per metre.
        pub bin_per_metre: f32,
        /// The collider bins' corner (x, z; m).
        pub bin_corner: [f32; 2],
        /// The collider bins' columns (along x).
        pub bin_columns: u32,
        /// The collider bins' rows (along z).
        pub bin_rows: u32,
        /// The turbulence's modes finer than the wind grid the tips sum
        /// (glsl/grass/step.glsl's `felt_at`); 0: none.
        pub subgrid_modes: u32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
    }

    /// Push constants of the collider-binning kernel
    /// (glsl/grass/bin_colliders.comp).
    pub struct BinPush {
        /// The bins' corner (x, z; m).
        pub corner: [f32; 2],
        /// Cells per metre.
        pub per_metre: f32,
        /// Time at the step's end (s).
        pub end_time: f32,
        /// Columns (along x).
        pub columns: u32,
        /// Rows (along z).
        pub rows: u32,
        /// Colliders to bin.
        pub collider_count: u32,
        /// The longest blade's reach, with a margin (m).
        pub reach: f32,
        /// The roots' lowest y (m).
        pub root_low: f32,
        /// The roots' highest y (m).
        pub root_high: f32,
    }

    /// Push constants of the cull pass's kernels (glsl/cull/).
    pub struct CullPush {
        /// World to clip space of the frame the depth pyramid holds.
        pub seen_from: Mat4Columns,
        /// Blades of the field (the flag kernel's batch starts at
        /// `first_blade`).
        pub blade_count: u32,
        /// Workgroups of the flag kernel over all blades.
        pub flag_groups: u32,
        /// 1 when shadows are on: shadow casters are listed.
        pub shadows: u32,
        /// The flag kernel's batch's first blade (a multiple of CULL_GROUP).
        pub first_blade: u32,
        /// The orientation test's cosine (`edge_on`; 1 = off).
        pub edge_on: f32,
        /// The pyramid's level 0 width.
        pub pyramid_width: u32,
        /// The pyramid's level 0 height.
        pub pyramid_height: u32,
        /// The pyramid's levels.
        pub pyramid_levels: u32,
        /// 1 when the pyramid holds a frame (0: no blade is occluded).
        pub pyramid_holds: u32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
    }

    /// One level of the depth pyramid: where its first texel lies in the
    /// pyramid's buffer (in floats) and its size.
    pub struct PyramidLevel {
        pub offset: u32,
        pub width: u32,
        pub height: u32,
    }

    /// Push constants of the depth pyramid's kernels (glsl/cull/pyramid_*).
    pub struct PyramidPush {
        /// The level read (the reduce kernel only).
        pub below: PyramidLevel,
        /// The level written.
        pub level: PyramidLevel,
    }

    /// Push constants of the cover's tile kernel (glsl/cover/tiles.comp;
    /// src/scene/cover/ makes the same blades on the CPU).
    pub struct CoverPush {
        /// Tile coordinates of the blade buffer's first tile.
        pub origin: [i32; 2],
        /// Tiles along each side of the square.
        pub side: u32,
        /// Blades in each tile.
        pub per_tile: u32,
        /// The buffer's blade the binding starts at (its batch), the
        /// binding's blade this dispatch starts at, and how many it makes.
        pub first: u32,
        pub start: u32,
        pub count: u32,
        /// The cover's seed, folded to 32 bits (`cover::seed32`).
        pub seed: u32,
        /// The kind weights summed: upright, upright + curved, all three
        /// (`cover::kind_thresholds`).
        pub kinds: [f32; 3],
        /// A tile's side (m).
        pub tile_m: f32,
        /// The blade shape's height and full width ranges (m).
        pub height: [f32; 2],
        pub width: [f32; 2],
        /// The buffer's blade the cover's first blade is (after the
        /// scene's patches).
        pub base: u32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
        /// Where blades grow: the least and greatest x and z (m), roots
        /// with min <= (x, z) < max (`Cover::bounds`); the others are made
        /// without width.
        pub bounds_min: [f32; 2],
        pub bounds_max: [f32; 2],
    }

    /// What the cover's tile kernel reads besides its push constants
    /// (glsl/cover/tiles.comp), written when the pass is made: the wind
    /// grid it samples and the blades' physics ranges, for their
    /// quasi-static pose.
    pub struct CoverParams {
        pub grid: WindGridParams,
        /// [min, max] of k_tip, k_root / k_tip and sigma
        /// (`[grass.dynamics]`).
        pub tip_stiffness: [f32; 2],
        pub stiffness_ratio: [f32; 2],
        pub sigma: [f32; 2],
        /// 1: the blades take their quasi-static pose in the wind; 0: they
        /// stand at rest (no wind to pose them in).
        pub pose: u32,
        /// 1: only blades the frame may draw are posed (the cull pass's
        /// tests on the box their reach allows, glsl/common/cull.glsl);
        /// the rest keep their rest shape, which no pass draws either.
        pub pose_drawn_only: u32,
        /// The tiles whose blades carry the paper's dynamics
        /// (`cover::kept_tiles`): the first, and how many a side; each
        /// blade's state at `cover::state_slot` x blades a tile + its index.
        pub kept_origin: [i32; 2],
        pub kept_side: u32,
        /// `simulate_radius` (m): the pressing fades out over the band
        /// inside it.
        pub simulate_radius: f32,
        /// The camera's x and z, which the radius is measured from.
        pub eye: [f32; 2],
        /// 1: the kept tiles' blades are posed from their states; 0: every
        /// blade quasi-static.
        pub dynamic: u32,
        /// 1: the kept blades keep pressed states (their dynamics were made
        /// with colliders), and their poses show them; 0: none kept.
        pub pressed_states: u32,
        /// [min, max] of the edge mass (kg, `[grass.dynamics]`): the far
        /// blades' natural frequency (`quasi_static::far_frequency`).
        pub edge_mass: [f32; 2],
        /// Simulated seconds since the last pass: how far a far blade goes
        /// towards its balance this frame (`quasi_static::far_tracked`).
        pub elapsed: f32,
        /// 1: a blade posed the frame before goes from that pose towards
        /// its balance as its dynamics could (`FarPose`); 0: it shows its
        /// balance at once, as if it had no past.
        pub far_tracking: u32,
        /// 1: the last poses are kept (binding 8 holds them); 0: the device
        /// cannot bind them whole, a placeholder stands there, and every
        /// blade shows its balance at once.
        pub far_kept: u32,
        /// An upper bound of the ground's slope |grad h| anywhere
        /// (`Terrain::max_slope`): blades whose every point the ground
        /// could not reach at that slope skip the fit's search.
        pub max_slope: f32,
        pub _pad0: u32,
        pub _pad1: u32,
    }

    /// A cover blade's pose the frame before, kept by the tile kernel in
    /// the slot its tile wraps to (`cover::state_slot` over the whole
    /// square; `CoverTilePass::far_poses`): what its quasi-static pose goes
    /// on from (`quasi_static::far_tracked`) and where its tip was.
    pub struct FarPose {
        /// The quasi-static part's angles (rad) and their rates (rad/s) as
        /// the tracking left them (a kept blade: its state's).
        pub angle: [f32; 4],
        pub velocity: [f32; 4],
        /// The drawn tip (m).
        pub tip: [f32; 3],
        /// Whose pose it is: `cover::far_tag` of the blade's tile (0: none,
        /// the blade was not posed).
        pub tile: u32,
    }

    /// The ground's height field as the GPU reads it
    /// (glsl/common/terrain.glsl; `Terrain::height` on the CPU, which
    /// `Terrain::gpu_words` packs): this header, then in the same buffer
    /// each hill's (x, z, H, L), each ridge's (x, z, H, L) and (cos, sin)
    /// of its heading, 4 floats each, then the height map's samples.
    pub struct TerrainHeader {
        /// The height map's samples along x and z (0, 0: no map).
        pub map_size: [u32; 2],
        /// Hills and ridges after the header.
        pub hills: u32,
        pub ridges: u32,
        /// The ground the map covers (x, z metres) and its centre.
        pub map_extent: [f32; 2],
        pub map_center: [f32; 2],
    }

    /// Push constants of the kernel that starts the cover's tiles coming
    /// into its simulated square at their quasi-static pose
    /// (glsl/cover/enter.comp).
    pub struct CoverEnterPush {
        pub grid: WindGridParams,
        /// The first blade (in the dynamics' slot order) and how many: one
        /// tile's.
        pub first: u32,
        pub count: u32,
        /// The tile's first blade among the tile kernel's last poses
        /// (`FarPose`; `cover::state_slot` over the whole square x blades
        /// a tile), and the tag a pose of this tile carries
        /// (`cover::far_tag`).
        pub far_first: u32,
        pub far_tag: u32,
    }

    /// Push constants of the bench's floor (glsl/bench/floor.vert).
    pub struct FloorPush {
        /// Quads along each blade.
        pub segments: u32,
    }

    /// Push constants of the obstacle pipelines (glsl/obstacle/): where a
    /// mesh's own frame lies in the world.
    pub struct Placement {
        /// The mesh's frame to world (rotation and translation), column-major.
        pub model: Mat4Columns,
    }

    /// The per-frame uniforms every render stage reads (glsl/common/frame.glsl,
    /// `frame`; made by src/render/frame_uniforms.rs from the scene's
    /// camera, light, level of detail and look). Only scalars, vectors and
    /// matrices, where std140 and std430 agree.
    pub struct FrameUniforms {
        pub view_proj: Mat4Columns,
        pub inv_view_proj: Mat4Columns,
        /// The eye in world space.
        pub camera_pos: [f32; 3],
        /// The sky's light on what the sun does not reach (its strength).
        pub ambient: f32,
        /// Unit vector toward the sun.
        pub light_dir: [f32; 3],
        /// What the fragment stage shows: VIEW_SHADED, VIEW_LOD,
        /// VIEW_MOTION or VIEW_DISPLACEMENT.
        pub view: u32,
        /// The sun's colour (linear).
        pub light_color: [f32; 3],
        /// 1: level of detail on; 0: every blade at the close level.
        pub lod_on: f32,
        /// The close, medium and far `tess_level` (paper section 5).
        pub tess_level: [f32; 3],
        /// Where the close level ends (m).
        pub lod_close_distance: f32,
        /// The shadow pass's `tess_level`, which its own copy of this block
        /// holds in `tess_level`: the scene's shadow levels with LOD on,
        /// the colour pass's levels with it off.
        pub shadow_tess_level: [f32; 3],
        /// Where the medium level ends (m).
        pub lod_far_distance: f32,
        /// World to the shadow map's clip space (orthographic, from the sun).
        pub light_view_proj: Mat4Columns,
        /// One shadow-map texel in uv; set by the renderer, which owns the map.
        pub shadow_texel: f32,
        /// 1: shadows on; 0: off.
        pub shadow_on: f32,
        /// The depth bias of the shadow test (clip-space depth).
        pub shadow_bias: f32,
        /// The spacing of the percentage-closer taps (texels).
        pub shadow_pcf_radius: f32,
        /// Distance thinning (glsl/common/thinning.glsl): the distance it
        /// begins (m), the least share kept, the band it fades over, and
        /// 1 = on (only with culling, which drops the blades it thins out).
        pub thinning_from: f32,
        pub thinning_least: f32,
        pub thinning_band: f32,
        pub thinning_on: f32,
        /// The clear ground lies around here (world x, z): the grass's
        /// centre, or the camera with a cover ...
        pub ground_center: [f32; 2],
        /// ... out to this far (m); the haze begins beyond.
        pub ground_clear: f32,
        /// The lowest ground the grass's shadows can fall on (m; 0 on flat
        /// ground).
        pub terrain_lowest: f32,
        /// The terrain mesh's centre (x, z) and half its side (m; 0: flat,
        /// no mesh; src/render/terrain.rs).
        pub terrain_center: [f32; 2],
        pub terrain_half_side: f32,
        /// The cover's leaf area index (0: none).
        pub cover_lai: f32,
        /// Where the cover grows: its least and greatest x, z (empty
        /// without one).
        pub cover_min: [f32; 2],
        pub cover_max: [f32; 2],
        /// The canopy map's least corner (x, z) and one over its extent;
        /// set by the renderer (`CanopyMap::placement`).
        pub canopy_map_min: [f32; 2],
        pub canopy_map_inverse_extent: [f32; 2],
        /// The canopy's top (m, the tallest blades).
        pub canopy_top: f32,
        /// 1: the canopy shades itself (glsl/common/canopy_light.glsl); 0: not.
        pub self_shadowing: f32,
        /// The leaf area index the canopy map's 1.0 stands for; set by the
        /// renderer, which owns the map (glsl/common/canopy.glsl).
        pub canopy_map_lai: f32,
        /// `[grass.look]` (glsl/common/grass_color.glsl).
        pub hue: f32,
        pub dryness: f32,
        pub tip: f32,
        /// The clumps' size (m).
        pub clump_size: f32,
        pub clump_variation: f32,
        pub sheen: f32,
        pub translucency: f32,
        /// The scene's seed's low 16 bits (exact in a float): the clumps' seed.
        pub clump_seed: f32,
        /// How far a caster's tessellated shadow may depart from its curve,
        /// in shadow-map texels (the scene's `lod.shadow_error_texels`; 0
        /// with LOD off or the rule off).
        pub shadow_error_texels: f32,
        /// A shadow-map texel's side in metres, in the shadow pass's copy
        /// of this block (src/render/shadow.rs); 0 in the colour pass's.
        pub shadow_texel_m: f32,
        /// How far a caster's tessellated shadow may depart from its
        /// curve, in pixels of the view at its nearest receiver (the
        /// scene's `lod.shadow_error_pixels`; 0 with LOD off or the rule
        /// off).
        pub shadow_error_pixels: f32,
        /// One pixel of the view across, per metre of depth in front of
        /// the eye: 2 tan(fov_y / 2) / height.
        pub pixel_per_depth_m: f32,
        pub _pad0: u32,
        /// The camera's unit forward direction (the view's axis).
        pub view_forward: [f32; 3],
        /// The least rise of a point in view per metre of its depth along
        /// `view_forward`: the steepest of the view's corner rays, down
        /// where negative (src/render/frame_uniforms.rs's `bottom_slope`).
        pub view_bottom_slope: f32,
    }
}
