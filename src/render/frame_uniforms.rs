//! The per-frame uniform block (glsl/common/frame.glsl), built from the
//! scene's camera, light and level-of-detail settings.

use ash::vk;
use glam::{Mat4, Vec3};

use crate::error::Result;
use crate::gpu::{Buffer, Gpu, MemoryLocation};
use crate::render::canopy_map;
use crate::render::shadow_frustum::light_view_proj;
use crate::render::shadow_params::ShadowParams;
use crate::render::terrain;
use crate::render::thinning::Thinning;
use crate::render::visibility::{filter_reach, CullView};
use crate::scene::Scene;

pub use crate::scene::ViewMode;

/// The block's fields, one name each (src/interface/defs.rs).
pub use crate::interface::FrameUniforms;

/// The camera at simulated time `time`, in Vulkan clip space: y points
/// down and depth runs 0..1.
pub fn view_projection(scene: &Scene, aspect: f32, time: f32) -> Mat4 {
    let (eye, target) = scene.camera.at(time);
    let view = Mat4::look_at_rh(eye, target, camera_up(target - eye));
    let mut proj = Mat4::perspective_rh(
        scene.camera.fov_y.to_radians(),
        aspect,
        0.05,
        crate::scene::check::VIEW_DISTANCE,
    );
    proj.y_axis.y = -proj.y_axis.y;
    proj * view
}

/// The least rise per metre of depth along `forward` of a point the view
/// `view_proj` from `eye` sees: the least over its four corner rays (the
/// view is the cone they span, and rise over depth, a ratio of two linear
/// functions, takes its least on the cone at one of them). A receiver no
/// higher than `top` is in view only at a depth of at least
/// `(eye.y - top) / -slope` where the slope is negative (blade.tesc's
/// `shadow_tolerance`).
pub fn bottom_slope(view_proj: &Mat4, eye: Vec3, forward: Vec3) -> f32 {
    let inverse = view_proj.inverse();
    [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
        .into_iter()
        .map(|(x, y)| {
            let ray = inverse.project_point3(Vec3::new(x, y, 0.5)) - eye;
            ray.y / ray.dot(forward).max(1e-6)
        })
        .fold(f32::INFINITY, f32::min)
}

/// The camera's up vector: the world's up, unless the camera looks (almost)
/// along it, where it is undefined: then the screen's up is world -z, as a
/// map shows north.
pub fn camera_up(forward: Vec3) -> Vec3 {
    let forward = forward.normalize_or_zero();
    if forward.y.abs() > 0.999 {
        Vec3::NEG_Z
    } else {
        Vec3::Y
    }
}

/// Where the cover's grass grows: its least and greatest x and z (zero
/// without a cover).
fn cover_corners(scene: &Scene) -> ([f32; 2], [f32; 2]) {
    match &scene.grass.cover {
        Some(cover) => {
            let [x0, z0, x1, z1] = cover.bounds();
            ([x0, z0], [x1, z1])
        }
        None => ([0.0; 2], [0.0; 2]),
    }
}

/// The terrain mesh drawn around `eye`: its lowest height, half side and
/// centre (zero on flat ground, which draws no mesh).
fn terrain_mesh(scene: &Scene, eye: Vec3) -> (f32, f32, [f32; 2]) {
    if scene.ground.terrain().is_flat() {
        (0.0, 0.0, [0.0; 2])
    } else {
        (
            terrain::lowest(scene, eye),
            terrain::half_side(scene.ground.half_extent),
            terrain::mesh_centre(scene, eye),
        )
    }
}

impl FrameUniforms {
    /// A host-visible uniform buffer holding one block, written each frame.
    pub fn buffer(gpu: &Gpu, name: &str) -> Result<Buffer> {
        Buffer::new(
            gpu,
            name,
            std::mem::size_of::<Self>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )
    }

    pub fn new(scene: &Scene, width: u32, height: u32, view: ViewMode, time: f32) -> Self {
        let view_proj = view_projection(scene, width as f32 / height as f32, time);
        let (eye, target) = scene.camera.at(time);
        let forward = (target - eye).normalize_or_zero();
        let light = Vec3::from(scene.light.direction)
            .try_normalize()
            .unwrap_or(Vec3::Y);
        let lod = &scene.lod;
        let look = &scene.grass.look;
        // The clear ground lies around the grass; a cover's grass lies
        // around the camera.
        let ground = match scene.grass.cover {
            Some(_) => eye,
            None => scene.grass_center(),
        };
        let thinning = Thinning::of(scene);
        let (cover_min, cover_max) = cover_corners(scene);
        let (terrain_lowest, terrain_half_side, terrain_center) = terrain_mesh(scene, eye);
        let on = |b: bool| if b { 1.0 } else { 0.0 };
        Self {
            view_proj: view_proj.to_cols_array_2d(),
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            camera_pos: eye.to_array(),
            ambient: scene.light.ambient,
            light_dir: light.to_array(),
            view: view as u32,
            light_color: scene.light.color,
            lod_on: on(lod.enabled),
            tess_level: tess_levels(lod.levels),
            lod_close_distance: lod.close_distance,
            shadow_tess_level: tess_levels(if lod.enabled {
                lod.shadow_levels
            } else {
                lod.levels
            }),
            lod_far_distance: lod.far_distance,
            light_view_proj: light_view_proj(scene, &view_proj).to_cols_array_2d(),
            thinning_from: thinning.from,
            thinning_least: thinning.least,
            thinning_band: thinning.band,
            thinning_on: on(thinning.is_on()),
            ground_center: [ground.x, ground.z],
            ground_clear: scene.ground.half_extent,
            terrain_lowest,
            terrain_center,
            terrain_half_side,
            cover_lai: canopy_map::cover_leaf_area_index(scene),
            cover_min,
            cover_max,
            canopy_top: scene.grass.shape.height[1],
            self_shadowing: on(scene.grass.look.self_shadowing),
            hue: look.hue,
            dryness: look.dryness,
            tip: look.tip,
            clump_size: look.clump_size,
            clump_variation: look.clump_variation,
            sheen: look.sheen,
            translucency: look.translucency,
            clump_seed: (scene.seed & 0xffff) as f32,
            shadow_error_texels: if lod.enabled {
                lod.shadow_error_texels
            } else {
                0.0
            },
            shadow_error_pixels: if lod.enabled {
                lod.shadow_error_pixels
            } else {
                0.0
            },
            pixel_per_depth_m: 2.0 * (scene.camera.fov_y.to_radians() * 0.5).tan()
                / height.max(1) as f32,
            view_forward: forward.to_array(),
            view_bottom_slope: bottom_slope(&view_proj, eye, forward),
            // The shadow map's and the canopy map's fields are the
            // renderer's, which owns the maps.
            ..Self::default()
        }
    }
}

impl FrameUniforms {
    /// The same instant in the data view of `--light-waves`: every blade
    /// its displacement, nothing else (`VIEW_DISPLACEMENT`).
    pub fn displacement_view(mut self) -> Self {
        self.view = crate::interface::VIEW_DISPLACEMENT;
        self
    }

    /// What the cull pass tests `scene`'s blades against in this frame
    /// (the CPU reference's view of it).
    pub fn cull_view(&self, scene: &Scene) -> CullView {
        let shadow = ShadowParams::of(scene.light.shadow_map);
        CullView {
            view_proj: Mat4::from_cols_array_2d(&self.view_proj),
            eye: Vec3::from(self.camera_pos),
            light: Vec3::from(self.light_dir),
            floor: self.terrain_lowest,
            shadows: shadow.on,
            thinning: Thinning::of(scene),
            edge_on: scene.cull.edge_on,
            filter_reach: filter_reach(&Mat4::from_cols_array_2d(&self.light_view_proj), shadow),
        }
    }
}

/// Close, medium and far tessellation levels as the `tess_level` vector.
fn tess_levels(levels: [u32; 3]) -> [f32; 3] {
    levels.map(|l| l as f32)
}
