//! The rendering phase of a frame (paper section 5): the shadow pass from
//! the sun, then the colour pass (sky, ground, and the grass through the
//! tessellation and geometry stages) resolved from MSAA, the depth pyramid
//! the next frame's occlusion test reads, then the copy of the frame into
//! host memory. Each step records into the frame's command
//! buffer; the frame recorder calls them in order and times them.

use crate::error::{Error, Result};
use crate::gpu::{
    Access, Attachments, Bound, Buffer, BufferUse, CommandPool, DescriptorSet, Gpu, ImageUse,
    Recording, TargetFormats,
};
use crate::model::collider::Collider;
use crate::model::wind::Obstacle;
use crate::render::canopy_map::CanopyMap;
use crate::render::cull::BladeDraw;
use crate::render::depth_pyramid::{DepthPyramid, Occluders};
use crate::render::frame_uniforms::FrameUniforms;
use crate::render::obstacles::ObstacleMeshes;
use crate::render::pipelines::{RenderPipelines, FRAME_SET};
use crate::render::shadow::ShadowMap;
use crate::render::targets::{choose_samples, RenderTargets};
use crate::render::terrain::{Grid, TerrainMesh};
use crate::render::textures::SurfaceTextures;

/// Everything one offscreen view of the grass needs on the GPU, besides
/// the blades themselves.
pub struct Renderer {
    frame_set: DescriptorSet,
    uniforms: Buffer,
    /// Sampled through the frame set.
    textures: SurfaceTextures,
    shadow: ShadowMap,
    obstacles: ObstacleMeshes,
    /// None on flat ground.
    terrain: Option<TerrainMesh>,
    pipelines: RenderPipelines,
    /// Built from the colour pass's depth each frame, with occlusion
    /// culling; its set samples the depth target, so it goes first.
    pyramid: Option<DepthPyramid>,
    targets: RenderTargets,
}

impl Renderer {
    /// Builds the targets and pipelines for a `width` x `height` image with
    /// up to `msaa` samples and a `shadow_map` x `shadow_map` shadow map (0:
    /// no shadows), drawing `obstacles`, `colliders` and the terrain's
    /// mesh `ground` (None: flat) among the grass;
    /// with `occlusion`, each frame's depth goes into a depth pyramid for
    /// the next frame's cull pass. `commands` uploads the surface textures
    /// and their meshes.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        gpu: &Gpu,
        commands: &CommandPool,
        (width, height): (u32, u32),
        msaa: u32,
        shadow_map: u32,
        obstacles: &[Obstacle],
        colliders: &[Collider],
        ground: Option<&Grid>,
        canopy: &CanopyMap,
        occlusion: bool,
    ) -> Result<Self> {
        let targets = RenderTargets::new(gpu, width, height, choose_samples(gpu, msaa), occlusion)?;
        let pyramid = occlusion
            .then(|| DepthPyramid::new(gpu, &targets.depth))
            .transpose()?;
        let pipelines = RenderPipelines::new(gpu, targets.formats(), shadow_map > 0)?;
        let max_side = gpu.limits().max_image_dimension2_d;
        if shadow_map > max_side {
            return Err(Error::InvalidInput(format!(
                "--shadow-map {shadow_map} is larger than this device's largest image ({max_side}); use 0..={max_side}"
            )));
        }
        let shadow = ShadowMap::new(gpu, shadow_map, &pipelines.shadow_layout)?;
        let uniforms = FrameUniforms::buffer(gpu, "frame uniforms")?;
        let textures = SurfaceTextures::new(gpu, commands, canopy)?;
        let obstacles = ObstacleMeshes::new(gpu, commands, obstacles, colliders)?;
        let terrain = ground
            .map(|grid| TerrainMesh::new(gpu, commands, grid))
            .transpose()?;
        let [map, map_sampler] = shadow.bindings();
        let [grass, ground, surface_sampler, canopy_map] = textures.bindings();
        let frame_set = DescriptorSet::new(
            gpu,
            &pipelines.frame_layout,
            FRAME_SET,
            &[
                Bound::Buffer(&uniforms),
                map,
                map_sampler,
                grass,
                ground,
                surface_sampler,
                canopy_map,
            ],
            "frame descriptor set",
        )?;
        Ok(Self {
            frame_set,
            uniforms,
            textures,
            shadow,
            obstacles,
            terrain,
            pipelines,
            pyramid,
            targets,
        })
    }

    /// Draws the terrain's mesh `ground` from the next frame on (a cover's,
    /// made about the camera as it moves): uploaded and waited for; the
    /// old mesh goes, so no frame using it may be in flight.
    pub fn set_terrain(&mut self, gpu: &Gpu, commands: &CommandPool, ground: &Grid) -> Result<()> {
        self.terrain = Some(TerrainMesh::new(gpu, commands, ground)?);
        Ok(())
    }

    /// The depth pyramid (None without occlusion culling).
    pub fn depth_pyramid(&self) -> Option<&DepthPyramid> {
        self.pyramid.as_ref()
    }

    /// A frame seen as `view_proj` is being recorded: what its cull pass
    /// tests blades against (None: nothing is occluded), its camera noted
    /// for the pyramid it builds.
    pub fn begin_frame(&mut self, view_proj: glam::Mat4) -> Option<Occluders> {
        self.pyramid.as_mut()?.begin_frame(view_proj)
    }

    /// The frame begun last finished (its depth built the pyramid) or not.
    pub fn end_frame(&mut self, finished: bool) {
        if let Some(p) = self.pyramid.as_mut() {
            p.end_frame(finished);
        }
    }

    /// The last frame's depth no longer stands for the next (the
    /// simulation jumped ahead).
    pub fn forget_depth(&mut self) {
        if let Some(p) = self.pyramid.as_mut() {
            p.forget();
        }
    }

    /// After the colour pass: this frame's depth into the pyramid.
    pub fn record_depth_pyramid(&self, rec: &Recording) {
        if let Some(p) = &self.pyramid {
            p.record_build(rec, &self.targets.depth);
        }
    }

    /// The MSAA sample count actually used.
    pub fn samples(&self) -> u32 {
        self.targets.color.samples.as_raw()
    }

    pub fn formats(&self) -> TargetFormats {
        self.targets.formats()
    }

    pub fn targets(&self) -> &RenderTargets {
        &self.targets
    }

    /// Sets this frame's camera, light and LOD (and the shadow map's own
    /// parameters) for both passes. Only between frames.
    pub fn set_uniforms(&mut self, uniforms: &FrameUniforms) {
        let mut uniforms = *uniforms;
        self.shadow.params().write(&mut uniforms);
        uniforms.canopy_map_lai = self.textures.canopy_scale;
        (uniforms.canopy_map_min, uniforms.canopy_map_inverse_extent) =
            self.textures.canopy_placement;
        self.uniforms.write(0, std::slice::from_ref(&uniforms));
        self.shadow.write_uniforms(&uniforms);
    }

    /// The colliders drawn.
    pub fn colliders(&self) -> &[Collider] {
        self.obstacles.colliders()
    }

    /// Draws the colliders where they are at simulated time `t` (s), from
    /// the next recorded frame on.
    pub fn place_colliders(&mut self, t: f32) {
        self.obstacles.place_colliders(t);
    }

    /// Draws `colliders` from now on (the viewer's ball coming, going,
    /// steered). Uploads and waits where their shapes change: call between
    /// submissions.
    pub fn set_colliders(
        &mut self,
        gpu: &Gpu,
        commands: &CommandPool,
        colliders: &[Collider],
    ) -> Result<()> {
        self.obstacles.set_colliders(gpu, commands, colliders)
    }

    /// The frame uniforms both passes (and the cull pass) read.
    pub fn uniforms(&self) -> &Buffer {
        &self.uniforms
    }

    /// Whether the shadow pass draws anything (a map and its pipelines).
    pub fn shadows(&self) -> bool {
        self.pipelines.shadow.is_some() && self.shadow.size > 0
    }

    /// The shadow pass: `draw` of `blades`, the obstacles, colliders and
    /// terrain from the sun.
    pub fn record_shadow(&self, rec: &Recording, blades: &Buffer, draw: BladeDraw) {
        self.shadow.record(
            rec,
            self.pipelines.shadow.as_ref(),
            blades,
            draw,
            &self.obstacles,
            self.terrain.as_ref(),
        );
    }

    /// Opens the colour pass: the targets cleared (after the previous
    /// frame's writes and read-back), the shadow map and the textures
    /// sampled; sky, ground (the terrain over its square) and obstacles.
    pub fn begin_color(&self, rec: &Recording) {
        let mut images = attachments(&self.targets);
        images.push(self.shadow.sampled());
        images.extend(self.textures.sampled());
        rec.declare(&[], &images);
        let t = &self.targets;
        rec.begin_rendering(&Attachments {
            color: Some((&t.color, t.resolve.as_ref())),
            depth: &t.depth,
            store_depth: self.pyramid.is_some(),
        });
        let p = &self.pipelines;
        rec.bind_set(&p.sky, &self.frame_set);
        rec.bind_pipeline(&p.sky);
        rec.draw(3);
        rec.bind_pipeline(&p.ground);
        rec.draw(3);
        if let Some(terrain) = &self.terrain {
            terrain.draw(rec, &p.terrain);
        }
        self.obstacles.draw(rec, &p.obstacle);
    }

    /// The grass: one 4-point patch per blade drawn, through all five
    /// stages.
    pub fn draw_grass(&self, rec: &Recording, blades: &Buffer, draw: BladeDraw) {
        rec.bind_pipeline(&self.pipelines.blade);
        draw.record(rec, blades);
    }

    /// Closes the colour pass (the MSAA image resolves at its end).
    pub fn end_color(&self, rec: &Recording) {
        rec.end_rendering();
    }

    /// Copies the final image into the host-visible read-back buffer.
    pub fn record_readback(&self, rec: &Recording) {
        let t = &self.targets;
        let final_image = t.final_image();
        rec.declare(
            &[BufferUse::new(&t.readback, Access::COPY_WRITE)],
            &[ImageUse::new(final_image, Access::COPY_READ)],
        );
        rec.copy_image_to_buffer(final_image, &t.readback);
        rec.uses(&[BufferUse::new(&t.readback, Access::HOST_READ)]);
    }

    /// Makes the final image ready to be blitted into a window (the
    /// viewer's way out instead of the read-back): its copy read declared.
    pub fn record_present_source(&self, rec: &Recording) {
        rec.declare(
            &[],
            &[ImageUse::new(self.targets.final_image(), Access::COPY_READ)],
        );
    }

    /// The frame read back by the last submitted `record_readback`: RGBA8,
    /// sRGB-encoded, rows top to bottom.
    pub fn pixels(&self) -> Vec<u8> {
        self.targets
            .readback
            .mapped()
            .expect("readback buffer is host-visible")
            .to_vec()
    }
}

/// `t`'s images as the colour pass's attachments, their contents dropped
/// (cleared, or resolved into); each first waits for whatever used it
/// before (the previous frame's pass, read-back and depth pyramid, or the
/// bench's floor).
pub fn attachments(t: &RenderTargets) -> Vec<ImageUse<'_>> {
    let mut uses = vec![
        ImageUse::discarding(&t.color, Access::COLOR_ATTACHMENT),
        ImageUse::discarding(&t.depth, Access::DEPTH_ATTACHMENT),
    ];
    if let Some(resolve) = &t.resolve {
        uses.push(ImageUse::discarding(
            resolve,
            Access::COLOR_ATTACHMENT_WRITE,
        ));
    }
    uses
}
