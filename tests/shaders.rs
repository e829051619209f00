//! The compiled shaders against the Rust side: naga parses and validates
//! every stage it supports, the descriptor-set layouts match what the
//! shaders declare, the uniform block and vertex layouts match byte for
//! byte, and every module passes spirv-val where it is installed.

use std::collections::BTreeSet;
use std::mem::offset_of;

use crate::common;

use ash::vk;
use common::reflect::{self, Binding};
use meadow::compute::grass_pass::grass_set;
use meadow::compute::wind_pass::{
    wind_set, GpuWindSource, WIND_KERNELS, WIND_KERNEL_VARIANTS, WIND_SHIFT_KERNEL,
};
use meadow::gpu::LayoutBinding;
use meadow::interface::{GpuColliderState, StructLayout, LAYOUTS};
use meadow::model::contact::GpuCollider;
use meadow::model::{BladeVertex, GrassBlade, GrassState};
use meadow::render::pipelines::{
    BLADE_ATTRIBUTES, BLADE_STAGES, FRAME_SET, GROUND_STAGES, OBSTACLE_SHADOW_STAGES,
    OBSTACLE_STAGES, SHADOW_SET, SHADOW_STAGES, SKY_STAGES, TERRAIN_SHADOW_STAGES, TERRAIN_STAGES,
};
use meadow::render::FrameUniforms;
use meadow::shaders::{self, ShaderStage, Spirv};

#[test]
fn every_stage_naga_supports_parses_and_validates() {
    let mut checked = 0;
    for spirv in shaders::ALL {
        if spirv.stage.naga_supported() {
            reflect::naga_module(spirv).unwrap_or_else(|e| panic!("{e}"));
            checked += 1;
        }
    }
    assert!(checked >= 6, "only {checked} modules checked");
}

#[test]
fn naga_and_the_decoration_scanner_agree() {
    for spirv in shaders::ALL.iter().filter(|s| s.stage.naga_supported()) {
        let used: BTreeSet<Binding> = reflect::naga_bindings(spirv).unwrap().into_iter().collect();
        let declared: BTreeSet<Binding> =
            reflect::scan_bindings(spirv).unwrap().into_iter().collect();
        // naga reports what the entry point uses; the scanner what is declared.
        assert!(
            used.is_subset(&declared),
            "{}: naga {used:?} vs scan {declared:?}",
            spirv.path
        );
    }
}

fn check_pipeline(name: &str, stages: &[&Spirv], layout: &[LayoutBinding]) {
    let mut used_by_some_stage = BTreeSet::new();
    for spirv in stages {
        let declared = reflect::scan_bindings(spirv).unwrap();
        for b in &declared {
            let rust = layout
                .iter()
                .find(|l| l.set == b.set && l.binding == b.binding)
                .unwrap_or_else(|| {
                    panic!(
                        "{name}: {} declares set {} binding {} missing from the Rust layout",
                        spirv.path, b.set, b.binding
                    )
                });
            assert_eq!(
                rust.ty, b.ty,
                "{name}: {} set {} binding {}",
                spirv.path, b.set, b.binding
            );
            assert!(
                rust.stages.contains(spirv.stage.vk()),
                "{name}: binding {}.{} is not visible to {:?} ({})",
                b.set,
                b.binding,
                spirv.stage,
                spirv.path
            );
        }
        let used = if spirv.stage.naga_supported() {
            reflect::naga_bindings(spirv).unwrap()
        } else {
            declared
        };
        used_by_some_stage.extend(used.iter().map(|b| (b.set, b.binding)));
    }
    for l in layout {
        assert!(
            used_by_some_stage.contains(&(l.set, l.binding)),
            "{name}: Rust layout has set {} binding {} that no shader uses",
            l.set,
            l.binding
        );
    }
}

#[test]
fn descriptor_layouts_match_reflection() {
    // The colour pass's pipelines share the frame set: together they use
    // every binding of it (the sky reads no shadow map).
    let color_pass: Vec<&Spirv> = BLADE_STAGES
        .iter()
        .chain(SKY_STAGES)
        .chain(GROUND_STAGES)
        .chain(OBSTACLE_STAGES)
        .chain(TERRAIN_STAGES)
        .copied()
        .collect();
    check_pipeline("colour pass", &color_pass, FRAME_SET);
    // The shadow pass: the blade stages up to the geometry shader, and the
    // obstacles' vertex shader.
    check_pipeline("shadow", SHADOW_STAGES, SHADOW_SET);
    check_pipeline("obstacle shadow", OBSTACLE_SHADOW_STAGES, SHADOW_SET);
    check_pipeline("terrain shadow", TERRAIN_SHADOW_STAGES, SHADOW_SET);
    // The wind kernels and the window's shift share one set layout.
    let wind: Vec<&Spirv> = WIND_KERNELS
        .iter()
        .chain(&WIND_KERNEL_VARIANTS)
        .chain(&[WIND_SHIFT_KERNEL])
        .copied()
        .collect();
    check_pipeline("wind", &wind, &wind_set());
    check_pipeline(
        "grass",
        &[
            &shaders::GRASS_STEP_COMP,
            &shaders::GRASS_STEP_TOUCHING_COMP,
        ],
        &grass_set(),
    );
    check_pipeline(
        "grass collider binning",
        &[&shaders::GRASS_BIN_COLLIDERS_COMP],
        &meadow::compute::collider_bins::bin_set(),
    );
    check_pipeline(
        "cover tiles",
        &[&shaders::COVER_TILES_COMP],
        &meadow::compute::cover_tiles::cover_set(),
    );
    check_pipeline(
        "cover enter",
        &[&shaders::COVER_ENTER_COMP],
        &meadow::compute::cover_dynamics::cover_enter_set(),
    );
    // The cull pass's three kernels share one set layout.
    check_pipeline(
        "cull",
        &[
            &shaders::CULL_FLAGS_COMP,
            &shaders::CULL_SCAN_COMP,
            &shaders::CULL_COMPACT_COMP,
        ],
        &meadow::render::cull::cull_set(),
    );
    // The depth pyramid's kernels (one of the two base kernels per
    // sample count) share one set layout.
    for base in [
        &shaders::CULL_PYRAMID_BASE_COMP,
        &shaders::CULL_PYRAMID_BASE_MULTISAMPLED_COMP,
    ] {
        check_pipeline(
            "depth pyramid",
            &[base, &shaders::CULL_PYRAMID_REDUCE_COMP],
            &meadow::render::depth_pyramid::pyramid_set(),
        );
    }
    // The bench's floor: vertex and fragment only.
    check_pipeline(
        "floor",
        meadow::render::floor::FLOOR_STAGES,
        meadow::render::floor::FLOOR_SET,
    );
    // Every stage the Rust layout exposes the block to is a stage that
    // declares it somewhere.
    let mut declaring = vk::ShaderStageFlags::empty();
    for spirv in BLADE_STAGES
        .iter()
        .chain(SKY_STAGES)
        .chain(GROUND_STAGES)
        .chain(OBSTACLE_STAGES)
        .chain(TERRAIN_STAGES)
    {
        if !reflect::scan_bindings(spirv).unwrap().is_empty() {
            declaring |= spirv.stage.vk();
        }
    }
    assert_eq!(FRAME_SET[0].stages, declaring);
}

#[test]
fn blade_pipeline_has_the_papers_five_stages() {
    let stages: Vec<ShaderStage> = BLADE_STAGES.iter().map(|s| s.stage).collect();
    assert_eq!(
        stages,
        [
            ShaderStage::Vertex,
            ShaderStage::TessellationControl,
            ShaderStage::TessellationEvaluation,
            ShaderStage::Geometry,
            ShaderStage::Fragment
        ]
    );
}

/// The frame block holds the interface's `FrameUniforms` whole, as
/// `frame`: its fields' offsets are every interface struct's test's
/// (`every_interface_struct_is_laid_out_in_each_shader_as_in_rust`), and
/// the block is no larger than the buffer the renderer writes.
#[test]
fn frame_uniforms_match_the_glsl_block() {
    let (span, members) = reflect::uniform_block_layout(&shaders::BLADE_BLADE_FRAG, 0, 0).unwrap();
    assert_eq!(span as usize, std::mem::size_of::<FrameUniforms>());
    assert_eq!(members, [("frame".to_string(), 0)]);
}

#[test]
fn blade_vertex_inputs_match_the_vertex_buffer_layout() {
    let (module, _) = reflect::naga_module(&shaders::BLADE_BLADE_VERT).unwrap();
    let ep = &module.entry_points[0];
    let mut inputs = Vec::new();
    for arg in &ep.function.arguments {
        if let Some(naga::Binding::Location { location, .. }) = arg.binding {
            let format = match module.types[arg.ty].inner {
                naga::TypeInner::Scalar(naga::Scalar::F32) => vk::Format::R32_SFLOAT,
                naga::TypeInner::Vector {
                    size: naga::VectorSize::Tri,
                    scalar: naga::Scalar::F32,
                } => vk::Format::R32G32B32_SFLOAT,
                ref other => panic!("location {location} is {other:?}"),
            };
            inputs.push((location, format));
        }
    }
    inputs.sort_by_key(|&(location, _)| location);
    let rust: Vec<_> = BLADE_ATTRIBUTES
        .iter()
        .map(|a| (a.location, a.format))
        .collect();
    assert_eq!(inputs, rust);
    // Each attribute one field of the vertex, in order.
    let offsets: Vec<u32> = BLADE_ATTRIBUTES.iter().map(|a| a.offset).collect();
    assert_eq!(offsets, blade_vertex_offsets());
    assert_eq!(std::mem::size_of::<BladeVertex>(), 32);
}

#[test]
fn every_module_passes_spirv_val_when_installed() {
    let available = std::process::Command::new("spirv-val")
        .arg("--version")
        .output()
        .is_ok();
    if !available {
        eprintln!("SKIPPED: spirv-val is not installed (Debian package spirv-tools)");
        return;
    }
    let dir = std::env::temp_dir().join(format!("meadow-spirv-val-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for spirv in shaders::ALL {
        let path = dir.join(spirv.path.replace('/', "_") + ".spv");
        std::fs::write(&path, spirv.bytes).unwrap();
        let out = std::process::Command::new("spirv-val")
            .args(["--target-env", "vulkan1.3"])
            .arg(&path)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}: {}",
            spirv.path,
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The name of the interface struct (src/interface/defs.rs) that is the
/// one member of the module's push-constant block, or None without a block.
/// Panics on a block of anything else: every push constant is written once.
fn push_constant_struct(spirv: &Spirv) -> Option<String> {
    let (module, _) = reflect::naga_module(spirv).unwrap();
    let push = module
        .global_variables
        .iter()
        .map(|(_, v)| v)
        .find(|v| v.space == naga::AddressSpace::PushConstant)?;
    let naga::TypeInner::Struct { members, .. } = &module.types[push.ty].inner else {
        panic!("{}: the push-constant block is no block", spirv.path)
    };
    let inner = match members.as_slice() {
        [one] => &module.types[one.ty],
        _ => panic!(
            "{}: the push-constant block has {} members; declare it as one struct of src/interface/defs.rs",
            spirv.path,
            members.len()
        ),
    };
    let name = inner.name.clone().unwrap_or_default();
    assert!(
        LAYOUTS.iter().any(|l| l.name == name),
        "{}: the push-constant block's member is `{name}`, not a struct of src/interface/defs.rs",
        spirv.path
    );
    Some(name)
}

/// Every struct of the interface that a shader declares, compared with
/// the Rust side field by field: name, offset and size, as naga reads the
/// compiled SPIR-V. (build.rs already checks the Rust offsets against
/// std430 at compile time; this reads what glslang actually laid out.)
#[test]
fn every_interface_struct_is_laid_out_in_each_shader_as_in_rust() {
    let mut seen = BTreeSet::new();
    for spirv in shaders::ALL.iter().filter(|s| s.stage.naga_supported()) {
        let (module, _) = reflect::naga_module(spirv).unwrap();
        for (_, ty) in module.types.iter() {
            let naga::TypeInner::Struct { members, span } = &ty.inner else {
                continue;
            };
            let Some(rust) = LAYOUTS.iter().find(|l| Some(l.name) == ty.name.as_deref()) else {
                continue;
            };
            let glsl: Vec<(String, usize)> = members
                .iter()
                .map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize))
                .collect();
            let expected: Vec<(String, usize)> = rust
                .fields
                .iter()
                .map(|&(n, o)| (n.to_string(), o))
                .collect();
            assert_eq!(glsl, expected, "{}: {}", spirv.path, rust.name);
            assert_eq!(
                *span as usize, rust.size,
                "{}: {}'s size",
                spirv.path, rust.name
            );
            seen.insert(rust.name);
        }
    }
    let unseen: Vec<&str> = LAYOUTS
        .iter()
        .map(|l: &StructLayout| l.name)
        .filter(|n| !seen.contains(n))
        .collect();
    assert!(unseen.is_empty(), "no shader declares {unseen:?}");
}

/// Each pipeline's push constants are the interface struct its Rust side
/// pushes, in every stage that declares them.
#[test]
fn every_push_constant_block_is_its_interface_struct() {
    let expect = |spirvs: &[&Spirv], name: &str| {
        for spirv in spirvs {
            assert_eq!(
                push_constant_struct(spirv).as_deref(),
                Some(name),
                "{}",
                spirv.path
            );
        }
    };
    expect(&WIND_KERNELS, "WindPush");
    expect(&WIND_KERNEL_VARIANTS, "WindPush");
    expect(&[WIND_SHIFT_KERNEL], "WindShiftPush");
    expect(
        &[
            &shaders::GRASS_STEP_COMP,
            &shaders::GRASS_STEP_TOUCHING_COMP,
        ],
        "GrassPush",
    );
    expect(&[&shaders::GRASS_BIN_COLLIDERS_COMP], "BinPush");
    expect(&[&shaders::COVER_TILES_COMP], "CoverPush");
    expect(&[&shaders::COVER_ENTER_COMP], "CoverEnterPush");
    expect(
        &[
            &shaders::CULL_FLAGS_COMP,
            &shaders::CULL_SCAN_COMP,
            &shaders::CULL_COMPACT_COMP,
        ],
        "CullPush",
    );
    expect(
        &[
            &shaders::CULL_PYRAMID_BASE_COMP,
            &shaders::CULL_PYRAMID_BASE_MULTISAMPLED_COMP,
            &shaders::CULL_PYRAMID_REDUCE_COMP,
        ],
        "PyramidPush",
    );
    expect(&[&shaders::BENCH_FLOOR_VERT], "FloorPush");
    expect(&[&shaders::OBSTACLE_OBSTACLE_VERT], "Placement");
    // No other stage declares push constants it would not be given.
    for spirv in shaders::ALL.iter().filter(|s| s.stage.naga_supported()) {
        push_constant_struct(spirv);
    }
}

/// Member offsets and size of a struct type in a naga module.
fn struct_layout(module: &naga::Module, ty: naga::Handle<naga::Type>) -> (Vec<u32>, u32) {
    match &module.types[ty].inner {
        naga::TypeInner::Struct { members, span } => {
            (members.iter().map(|m| m.offset).collect(), *span)
        }
        other => panic!("not a struct: {other:?}"),
    }
}

#[test]
fn wind_sources_and_colliders_match_the_glsl_side() {
    let (module, _) = reflect::naga_module(&shaders::WIND_FORCES_COMP).unwrap();
    // The sources buffer: a block whose one member is a runtime array of WindSource.
    let (offsets, span, stride) = array_element_layout(&module, 5);
    assert_eq!(stride as usize, std::mem::size_of::<GpuWindSource>());
    assert_eq!(span as usize, std::mem::size_of::<GpuWindSource>());
    assert_eq!(
        offsets,
        [
            offset_of!(GpuWindSource, position),
            offset_of!(GpuWindSource, radius),
            offset_of!(GpuWindSource, direction),
            offset_of!(GpuWindSource, strength),
            offset_of!(GpuWindSource, gust_phases),
            offset_of!(GpuWindSource, gust_amplitude),
            offset_of!(GpuWindSource, gust_frequency),
            offset_of!(GpuWindSource, rotation_speed),
            offset_of!(GpuWindSource, path_speed),
            offset_of!(GpuWindSource, off_after),
            offset_of!(GpuWindSource, path_points),
            offset_of!(GpuWindSource, _pad0),
            offset_of!(GpuWindSource, _pad1),
            offset_of!(GpuWindSource, _pad2),
            offset_of!(GpuWindSource, path),
        ]
        .map(|o| o as u32)
    );
    // The colliders the forces kernel reads, as the grass kernel does.
    let (_, span, stride) = array_element_layout(&module, 10);
    assert_eq!(stride as usize, std::mem::size_of::<GpuCollider>());
    assert_eq!(span as usize, std::mem::size_of::<GpuCollider>());
}

/// Offsets and size of the element struct of the runtime array that is
/// the only member of the storage block at (0, binding).
fn array_element_layout(module: &naga::Module, binding: u32) -> (Vec<u32>, u32, u32) {
    let block = reflect::resource_at(module, 0, binding).expect("a storage block");
    let naga::TypeInner::Struct { members, .. } = &module.types[block.ty].inner else {
        panic!("binding {binding} is not a block")
    };
    assert_eq!(members.len(), 1, "binding {binding}: one runtime array");
    let naga::TypeInner::Array { base, stride, .. } = module.types[members[0].ty].inner else {
        panic!("binding {binding} is not an array")
    };
    let (offsets, span) = struct_layout(module, base);
    (offsets, span, stride)
}

/// Each of `BladeVertex`'s fields' offset, in order.
fn blade_vertex_offsets() -> [u32; 4] {
    [
        offset_of!(BladeVertex, position),
        offset_of!(BladeVertex, blade_rand),
        offset_of!(BladeVertex, half_width),
        offset_of!(BladeVertex, displacement),
    ]
    .map(|o| o as u32)
}

/// The storage array at `binding` is laid out as `BladeVertex`.
fn assert_blade_vertices(module: &naga::Module, binding: u32) {
    let (offsets, span, stride) = array_element_layout(module, binding);
    assert_eq!(span as usize, std::mem::size_of::<BladeVertex>());
    assert_eq!(stride as usize, std::mem::size_of::<BladeVertex>());
    assert_eq!(offsets, blade_vertex_offsets());
}

#[test]
fn the_cull_pass_reads_the_vertices_the_grass_step_writes() {
    let (module, _) = reflect::naga_module(&shaders::CULL_FLAGS_COMP).unwrap();
    assert_blade_vertices(&module, 1);
}

#[test]
fn the_cover_writes_the_vertices_the_draw_reads() {
    let (module, _) = reflect::naga_module(&shaders::COVER_TILES_COMP).unwrap();
    assert_blade_vertices(&module, 1);
}

#[test]
fn grass_blade_state_vertex_and_push_constants_match_the_glsl_side() {
    let (module, _) = reflect::naga_module(&shaders::GRASS_STEP_COMP).unwrap();
    let size = |n: usize| n as u32;

    let (offsets, span, stride) = array_element_layout(&module, 0);
    assert_eq!((span, stride), (size(144), size(144)));
    assert_eq!(std::mem::size_of::<GrassBlade>(), 144);
    assert_eq!(
        offsets,
        [
            offset_of!(GrassBlade, rest_root),
            offset_of!(GrassBlade, blade_rand),
            offset_of!(GrassBlade, rest_1),
            offset_of!(GrassBlade, ground_normal_x),
            offset_of!(GrassBlade, rest_2),
            offset_of!(GrassBlade, ground_curvature),
            offset_of!(GrassBlade, rest_tip),
            offset_of!(GrassBlade, ground_normal_z),
            offset_of!(GrassBlade, width_dir),
            offset_of!(GrassBlade, half_width),
            offset_of!(GrassBlade, stiffness),
            offset_of!(GrassBlade, group_b_edge),
            offset_of!(GrassBlade, drag),
            offset_of!(GrassBlade, inertia),
            offset_of!(GrassBlade, damping),
        ]
        .map(|o| o as u32)
    );

    let (offsets, span, stride) = array_element_layout(&module, 1);
    assert_eq!((span, stride), (size(32), size(32)));
    assert_eq!(std::mem::size_of::<GrassState>(), 32);
    assert_eq!(
        offsets,
        [
            offset_of!(GrassState, angle),
            offset_of!(GrassState, velocity)
        ]
        .map(|o| o as u32)
    );

    // The kernel writes what the vertex stage reads.
    assert_blade_vertices(&module, 2);

    // The pressed state and the colliders (src/model/contact.rs).
    use meadow::model::contact::Press;
    let (offsets, span, stride) = array_element_layout(&module, 6);
    assert_eq!((span, stride), (size(8), size(8)));
    assert_eq!(std::mem::size_of::<Press>(), 8);
    assert_eq!(
        offsets,
        [offset_of!(Press, pressed), offset_of!(Press, touched)].map(|o| o as u32)
    );
    // The colliders' states at the step's end, as the binning kernel
    // writes them and `ColliderBins::read_states` reads them: a, radius;
    // b; velocity.
    let state_offsets = [
        offset_of!(GpuColliderState, a),
        offset_of!(GpuColliderState, radius),
        offset_of!(GpuColliderState, b),
        offset_of!(GpuColliderState, _pad0),
        offset_of!(GpuColliderState, velocity),
        offset_of!(GpuColliderState, _pad1),
    ]
    .map(|o| o as u32);
    assert_eq!(state_offsets, [0, 12, 16, 28, 32, 44]);
    let (offsets, span, stride) = array_element_layout(&module, 7);
    assert_eq!((span, stride), (size(48), size(48)));
    assert_eq!(offsets, state_offsets);
    let (bins, _) = reflect::naga_module(&shaders::GRASS_BIN_COLLIDERS_COMP).unwrap();
    let (offsets, span, stride) = array_element_layout(&bins, 1);
    assert_eq!((span, stride), (size(48), size(48)));
    assert_eq!(offsets, state_offsets);
    // The colliders as the binning kernel reads them.
    let (offsets, span, stride) = array_element_layout(&bins, 0);
    assert_eq!((span, stride), (size(176), size(176)));
    assert_eq!(std::mem::size_of::<GpuCollider>(), 176);
    assert_eq!(
        offsets,
        [
            offset_of!(GpuCollider, position),
            offset_of!(GpuCollider, radius),
            offset_of!(GpuCollider, capsule),
            offset_of!(GpuCollider, height),
            offset_of!(GpuCollider, path_points),
            offset_of!(GpuCollider, path_speed),
            offset_of!(GpuCollider, closed),
            offset_of!(GpuCollider, sets_off),
            offset_of!(GpuCollider, _pad0),
            offset_of!(GpuCollider, _pad1),
            offset_of!(GpuCollider, path),
        ]
        .map(|o| o as u32)
    );
}
