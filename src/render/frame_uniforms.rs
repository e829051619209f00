//! The per-frame uniform block (glsl/common/frame.glsl), built from the
//! scene's camera, light and level-of-detail settings.

use ash::vk;
use glam::{Mat4, Vec3};

use crate::error::Result;
use crate::gpu::{Buffer, Gpu, MemoryLocation};
use crate::render::canopy_map;
use crate::render::shadow_frustum::light_view_proj;
use crate::render::terrain;
use crate::render::thinning::Thinning;
use crate::scene::Scene;

pub use crate::scene::ViewMode;

/// std140 mirror of `Frame` in glsl/common/frame.glsl; a test compares the
/// member offsets with naga's reading of the compiled shader.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct FrameUniforms {
    pub view_proj: [f32; 16],
    pub inv_view_proj: [f32; 16],
    pub camera_pos: [f32; 4],
    pub light_dir: [f32; 4],
    pub light_color: [f32; 4],
    pub lod_distance: [f32; 4],
    pub tess_level: [f32; 4],
    pub ground: [f32; 4],
    pub view: [u32; 4],
    /// World to the shadow map's clip space (`light_view_proj`).
    pub light_view_proj: [f32; 16],
    /// x: one shadow-map texel in uv, y: 1 = shadows on, z: depth bias,
    /// w: PCF tap spacing in texels. Set by the renderer, which owns the map.
    pub shadow: [f32; 4],
    /// x: distance thinning begins (m), y: least share kept, z: band, w:
    /// 1 = on (only with culling, which drops the blades it thins out).
    /// Off, the share is 1 everywhere and every scale is 1.
    pub thinning: [f32; 4],
    /// The shadow pass's `tess_level` (its own copy of this block holds
    /// it there): the scene's shadow levels with LOD on, the colour
    /// pass's close level with it off.
    pub shadow_tess_level: [f32; 4],
    /// x: the lowest ground the grass's shadows can fall on (m; 0 on flat
    /// ground); y: half the side of the terrain mesh's square (0: flat, no
    /// mesh; src/render/terrain.rs); zw: its centre (x, z).
    pub terrain: [f32; 4],
    /// x: the cover's leaf area index (0: none); y: the canopy's top (m,
    /// the tallest blades); z: 1 = self-shadowing on; w: the leaf area
    /// index the canopy map's 1.0 stands for (set by the renderer, which
    /// owns the map; glsl/common/canopy.glsl).
    pub canopy: [f32; 4],
    /// The canopy map's least corner (x, z) and one over its extent; set
    /// by the renderer (`CanopyMap::placement`).
    pub canopy_map: [f32; 4],
    /// Where the cover grows: x0, z0, x1, z1 (empty without one).
    pub cover_bounds: [f32; 4],
    /// `[grass.look]`: hue, dryness, tip, clump_size.
    pub look: [f32; 4],
    /// `[grass.look]`: clump_variation, sheen, translucency; w: the
    /// scene's seed's low 16 bits (exact in a float), the clumps' seed.
    pub look_more: [f32; 4],
}

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
        let (eye, _) = scene.camera.at(time);
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
        Self {
            view_proj: view_proj.to_cols_array(),
            inv_view_proj: view_proj.inverse().to_cols_array(),
            camera_pos: eye.extend(1.0).to_array(),
            light_dir: light.extend(scene.light.ambient).to_array(),
            light_color: Vec3::from(scene.light.color).extend(0.0).to_array(),
            lod_distance: [
                lod.close_distance,
                lod.far_distance,
                if lod.enabled { 1.0 } else { 0.0 },
                0.0,
            ],
            tess_level: tess_levels(lod.levels),
            ground: [ground.x, ground.z, scene.ground.half_extent, 0.0],
            view: [view as u32, 0, 0, 0],
            light_view_proj: light_view_proj(scene, &view_proj).to_cols_array(),
            shadow: [0.0; 4],
            thinning: Thinning::of(scene).uniform(),
            shadow_tess_level: tess_levels(if lod.enabled {
                lod.shadow_levels
            } else {
                lod.levels
            }),
            canopy: [
                canopy_map::cover_leaf_area_index(scene),
                scene.grass.shape.height[1],
                if scene.grass.look.self_shadowing {
                    1.0
                } else {
                    0.0
                },
                0.0,
            ],
            canopy_map: [0.0; 4],
            cover_bounds: match &scene.grass.cover {
                Some(cover) => cover.bounds(),
                None => [0.0; 4],
            },
            look: [look.hue, look.dryness, look.tip, look.clump_size],
            look_more: [
                look.clump_variation,
                look.sheen,
                look.translucency,
                (scene.seed & 0xffff) as f32,
            ],
            terrain: if scene.ground.terrain().is_flat() {
                [0.0; 4]
            } else {
                let centre = terrain::mesh_centre(scene, eye);
                [
                    terrain::lowest(scene, eye),
                    terrain::half_side(scene.ground.half_extent),
                    centre[0],
                    centre[1],
                ]
            },
        }
    }
}

impl FrameUniforms {
    /// The same instant in the data view of `--light-waves`: every blade
    /// its displacement, nothing else (`VIEW_DISPLACEMENT`).
    pub fn displacement_view(mut self) -> Self {
        self.view[0] = crate::interface::VIEW_DISPLACEMENT;
        self
    }
}

/// Close, medium and far tessellation levels as the `tess_level` vector.
fn tess_levels(levels: [u32; 3]) -> [f32; 4] {
    [levels[0] as f32, levels[1] as f32, levels[2] as f32, 0.0]
}
