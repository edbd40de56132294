//! A directional light's cascaded shadow map, as the benchmark draws it:
//! each cascade an orthographic view fitted around a slice of the camera's
//! frustum, drawn with depth bias into one layer of a depth array (on GL,
//! whose backend samples only layer 0 of an array, a texture each). Each
//! cascade also writes object IDs (a shadow pass needs none; the benchmark
//! checks every cascade against `noc` with them, and HROC's occluder
//! filtering reads them).
//!
//! Culling a cascade is culling its own view against its own depth: a
//! caster hidden from the camera can still cast a visible shadow, so
//! nothing here culls casters against the camera's depth.

use glam::{Mat4, Vec3};

use super::{color_attachment, draw_pipeline, id_format, target_of, DrawList, Renderer, ViewUniform, DEPTH_FORMAT};
use crate::error::{Error, Result};
use crate::gpu::Headless;
use crate::scene::{Aabb, Camera};

/// Width and height of every cascade.
pub const CASCADE_SIZE: u32 = 512;

/// The cascades' depth bias, away from the light (standard depth: ≥ 0), as
/// shadow passes bias against acne.
pub const SHADOW_BIAS: wgpu::DepthBiasState = wgpu::DepthBiasState { constant: 2, slope_scale: 1.5, clamp: 0.0 };

/// Most cascades a light has.
pub const MAX_CASCADES: u32 = 4;

/// One cascade's view of the scene: a right-handed orthographic projection
/// looking along the light (the scene crate's `Cascade`, projected).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CascadeView {
    pub view: Mat4,
    pub proj: Mat4,
}

impl CascadeView {
    /// The cascade as the culler sees it (standard depth, clipped).
    pub fn view_desc(&self) -> hroc::ViewDesc {
        hroc::ViewDesc { view: self.view, proj: self.proj, unclipped_depth: false }
    }
}

/// `count` cascades of a light shining along `-toward_light` onto `scene`,
/// for `camera` (aspect `aspect`), in standard depth
/// ([`crate::scene::camera::cascades`]).
pub fn fit(camera: &Camera, aspect: f32, toward_light: Vec3, scene: &Aabb, count: u32) -> Vec<CascadeView> {
    crate::scene::camera::cascades(camera, aspect, toward_light, scene, count).iter().map(|c| CascadeView { view: c.view, proj: c.proj(false) }).collect()
}

/// The cascades' targets and pipelines: one depth array of `count`
/// layers (on GL, `count` depth textures), an ID target per cascade, and a
/// uniform per cascade.
pub struct Cascades {
    pub count: u32,
    depth: Vec<wgpu::Texture>,
    pub ids: Vec<wgpu::Texture>,
    layers: Vec<wgpu::TextureView>,
    id_views: Vec<wgpu::TextureView>,
    uniforms: Vec<wgpu::Buffer>,
    binds: Vec<wgpu::BindGroup>,
    draw: wgpu::RenderPipeline,
    draw_mark: wgpu::RenderPipeline,
}

impl Cascades {
    /// `count` cascades (1 to [`MAX_CASCADES`]) drawn with `r`'s shader.
    pub fn new(gpu: &Headless, r: &Renderer, count: u32) -> Result<Cascades> {
        if !(1..=MAX_CASCADES).contains(&count) {
            return Err(Error::Options(format!("--shadow-cascades {count}: a light has 1 to {MAX_CASCADES} cascades")));
        }
        let depth: Vec<wgpu::Texture> = match gpu.info.backend {
            wgpu::Backend::Gl => (0..count).map(|_| target_of(gpu, "shadow cascade", (CASCADE_SIZE, CASCADE_SIZE, 1), 1, DEPTH_FORMAT)).collect(),
            _ => vec![target_of(gpu, "shadow cascades", (CASCADE_SIZE, CASCADE_SIZE, count), 1, DEPTH_FORMAT)],
        };
        let ids: Vec<wgpu::Texture> = (0..count).map(|_| target_of(gpu, "cascade ids", (CASCADE_SIZE, CASCADE_SIZE, 1), 1, id_format(1))).collect();
        let mut cascades = Cascades {
            count,
            depth,
            ids,
            layers: Vec::new(),
            id_views: Vec::new(),
            uniforms: Vec::new(),
            binds: Vec::new(),
            draw: draw_pipeline(gpu, &r.module, &r.layout, false, false, SHADOW_BIAS, 1),
            draw_mark: draw_pipeline(gpu, &r.module, &r.layout, true, false, SHADOW_BIAS, 1),
        };
        cascades.layers = (0..count)
            .map(|c| {
                let (texture, layer) = cascades.depth_of(c);
                texture.create_view(&wgpu::TextureViewDescriptor {
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: layer,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        use wgpu::BufferUsages as U;
        let uniforms: Vec<wgpu::Buffer> = (0..count).map(|_| gpu.buffer("cascade view", std::mem::size_of::<ViewUniform>() as u64, U::UNIFORM | U::COPY_DST)).collect();
        cascades.binds = uniforms.iter().map(|u| gpu.bind_buffers(&r.frame_layout, &[u, &r.objects])).collect();
        cascades.uniforms = uniforms;
        cascades.id_views = cascades.ids.iter().map(|t| t.create_view(&Default::default())).collect();
        Ok(cascades)
    }

    /// The depth texture cascade `c` draws into, and its layer there.
    pub fn depth_of(&self, c: u32) -> (&wgpu::Texture, u32) {
        match self.depth.len() {
            1 => (&self.depth[0], c),
            _ => (&self.depth[c as usize], 0),
        }
    }

    /// Cascade `c`'s targets as its view of the culler sees them: its layer
    /// of the depth array, and its ID target.
    pub fn view_targets(&self, c: u32) -> hroc::ViewTargets<'_> {
        let (depth, layer) = self.depth_of(c);
        hroc::ViewTargets::new(depth, hroc::DepthRange::Standard).with_ids(&self.ids[c as usize]).at(layer, 0)
    }

    /// Writes cascade `c`'s view-projection.
    pub fn write_view(&self, gpu: &Headless, c: u32, cascade: &CascadeView) {
        let u = ViewUniform { view_proj: (cascade.proj * cascade.view).to_cols_array_2d(), light_dir: [0.0; 4] };
        gpu.queue.write_buffer(&self.uniforms[c as usize], 0, bytemuck::bytes_of(&u));
    }

    /// A pass over cascade `c`'s targets, clearing them (depth to far, IDs
    /// to 0) or loading them.
    fn pass<'e>(&self, enc: &'e mut wgpu::CommandEncoder, c: u32, clear: bool) -> wgpu::RenderPass<'e> {
        let c = c as usize;
        enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(if clear { "cascade clear" } else { "cascade draw" }),
            color_attachments: &[Some(color_attachment(&self.id_views[c], clear.then_some(wgpu::Color::TRANSPARENT)))],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.layers[c],
                depth_ops: Some(wgpu::Operations { load: if clear { wgpu::LoadOp::Clear(1.0) } else { wgpu::LoadOp::Load }, store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }

    /// Clears cascade `c`'s targets.
    pub fn clear(&self, enc: &mut wgpu::CommandEncoder, c: u32) {
        drop(self.pass(enc, c, true));
    }
}

/// The renderer drawing cascade `c` for one frame, as a [`hroc::DrawHost`]:
/// every list into the cascade's layer (depth-biased, no colour), keeping
/// the lists as [`super::Recorder`] does.
pub struct CascadeRecorder<'r> {
    pub renderer: &'r Renderer,
    pub cascades: &'r Cascades,
    pub cascade: u32,
    pub lists: Vec<DrawList>,
}

impl hroc::DrawHost for CascadeRecorder<'_> {
    fn draw(&mut self, enc: &mut wgpu::CommandEncoder, d: &hroc::Draw<'_>) {
        let s = self.cascades;
        let mut pass = s.pass(enc, self.cascade, false);
        pass.set_bind_group(0, &s.binds[self.cascade as usize], &[]);
        pass.set_vertex_buffer(0, self.renderer.vertices.slice(..));
        pass.set_index_buffer(self.renderer.indices.slice(..), wgpu::IndexFormat::Uint32);
        d.record(&mut pass, if d.mark { &s.draw_mark } else { &s.draw }, 1);
        drop(pass);
        self.lists.push(DrawList { commands: d.commands.clone(), count: d.count.clone(), max_count: d.max_count });
    }
}
