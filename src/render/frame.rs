//! The frame, in order, as `systems/src/schedule.rs` is for the simulation:
//!
//! 1. **Extract** ([`FrameData::extract`]): copy what is drawn out of the world.
//! 2. **Prepare**: the frame-wide choices (shadows on or off, the wind model: one
//!    [`PipelineKey`]), then each feature's buffers and pipelines ([`Feature::prepare`]), then the
//!    views' uniforms (the shadow map is fitted to what the features drew).
//! 3. **Compute**: the grass blades are culled into draw lists and indirect draw counts.
//! 4. **Shadow**: depth from the sun of every shadow caster ([`Feature::draw_depth`]).
//!    **Water views** (only with water): the reflection (trees, ground, sky from the mirrored
//!    camera) and the refraction (trees and ground below the surface), at half resolution.
//! 5. **Main**: the phases in order ([`Phase`]): opaque, alpha-clipped, sky, blended, overlay.
//! 6. **Resolve** the pass timestamps.
//!
//! Features are named fields of the renderer called here in a visible order; there is no
//! render graph and no registry. A new feature is a folder with its module and shader, one
//! field and one line in each stage it takes part in (see ARCHITECTURE.md).

use glam::Vec3;
use grove_systems::Sim;

use super::extract::FrameData;
use super::gpu::{PipelineKey, Shared, ViewKind};
use super::lighting::{light_matrix, shadow_bounds, sun_light};
use super::view::{camera_matrix, ViewUniform};
use super::{FrameStats, RenderOptions, Renderer};

/// The phases of the main pass, in the order they are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Opaque surfaces, depth-tested and written.
    Opaque,
    /// Alpha-clipped surfaces: a depth pre-pass, then shading at equal depth.
    AlphaClipped,
    /// The background, at the far plane, where nothing was drawn.
    Sky,
    /// Blended surfaces, far to near, depth-tested but not written (none yet).
    Blended,
    /// Interaction visuals, last.
    Overlay,
}

/// What a feature's [`Feature::prepare`] sees of the frame.
pub(crate) struct FrameContext<'a> {
    /// The device, queue and shared layouts.
    pub shared: &'a Shared,
    /// What the frame draws.
    pub data: &'a FrameData,
    /// The main view's pipeline key; a feature that casts shadows also prepares the sun's
    /// (`key.with_view(ViewKind::Sun)`) when `key.shadows` is set.
    pub key: PipelineKey,
    /// The target's size, pixels.
    pub size: (u32, u32),
    /// The renderer's options.
    pub options: &'a RenderOptions,
}

/// The interface between the frame and a drawn feature.
pub(crate) trait Feature {
    /// Uploads this frame's data and builds the pipelines of `cx.key` on first use. Fails for
    /// a key the feature has no pipeline for.
    fn prepare(&mut self, cx: &FrameContext<'_>) -> Result<(), String>;

    /// Draws depth only from the sun into the shadow map (shadow casters only), with the
    /// pipelines of `key` (the sun's view).
    fn draw_depth<'p>(&'p self, _pass: &mut wgpu::RenderPass<'p>, _key: PipelineKey) -> Result<(), String> {
        Ok(())
    }

    /// Draws the feature's part of `phase` in the main pass, with the pipelines of `key`. The
    /// frame has bound group 0 (the view) and group 1 (the lighting); a feature binds group 2.
    fn draw<'p>(&'p self, phase: Phase, pass: &mut wgpu::RenderPass<'p>, key: PipelineKey, stats: &mut FrameStats) -> Result<(), String>;
}

impl Renderer {
    /// Records one frame of `sim` into `encoder`, drawing into `view`.
    pub(crate) fn encode_frame(&mut self, sim: &Sim, view: &wgpu::TextureView, encoder: &mut wgpu::CommandEncoder) -> Result<(), String> {
        // 1. Extract.
        let mut data = FrameData::extract(sim, &self.ground.key);
        if let Some(top) = self.options.top_view {
            data.camera = top.camera();
        } else if let Some(camera) = self.options.camera {
            // Markers keep their size as seen from the camera drawn from.
            data.camera = camera;
            data.overlay.eye = camera.position;
        }
        data.overlay.ghosts.clone_from(&self.ghosts);
        if self.options.grass {
            data.extract_grass(sim, &self.grass.key);
        }
        // Without a canopy the photographed crowns are trees like the others.
        if self.canopy.is_none() || !self.options.canopy {
            let crown_trees = std::mem::take(&mut data.crown_trees);
            data.trees.extend(crown_trees);
            data.crowns.clear();
        }

        // 2. Prepare. Shadows are decided here and only here: asked for, the sun up, and
        // something to cast them.
        self.lighting.set_shadow_size(&self.shared, self.options.shadow_size);
        let light = sun_light(data.sun_elevation_deg);
        let options = self.options;
        let mut cx = FrameContext {
            shared: &self.shared,
            data: &data,
            key: PipelineKey { shadows: false, wind: data.wind_model, format: self.format, view: ViewKind::Main },
            size: (self.width, self.height),
            options: &options,
        };
        cx.key.shadows = options.shadows && light.direct.max_element() > 0.0 && (self.trees.draws_any(&cx) || self.canopy.as_ref().is_some_and(|c| c.draws_any(&cx)));
        let key = cx.key;
        self.trees.prepare(&cx)?;
        self.ground.prepare(&cx)?;
        self.grass.prepare(&cx)?;
        self.sky.prepare(&cx)?;
        self.overlay.prepare(&cx)?;
        self.water.prepare(&cx)?;
        if let Some(a) = &mut self.aerial_ground {
            a.prepare(&cx)?;
        }
        if let Some(c) = &mut self.canopy {
            c.prepare(&cx)?;
        }

        // The views: the camera's, and the sun's fitted to the trees and planes within 80 m of
        // the camera.
        let view_proj = match options.top_view {
            Some(top) => top.matrix(),
            None => camera_matrix(&data.camera, self.width as f32 / self.height as f32),
        };
        let drawn = union(union(self.trees.bounds, data.plane_bounds), self.canopy.as_ref().and_then(|c| c.bounds));
        let (smin, smax) = shadow_bounds(drawn, data.camera.position);
        let (light_vp, extent) = light_matrix(data.sun_dir, smin, smax);
        let shadow_size = self.lighting.shadow_size as f32;
        let main = ViewUniform {
            view_proj: view_proj.to_cols_array_2d(),
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            light_view_proj: light_vp.to_cols_array_2d(),
            camera_pos: data.camera.position.to_array(),
            time: (data.time % 3600.0) as f32,
            sun_dir: data.sun_dir.to_array(),
            pad0: 0.0,
            sun_color: light.direct.to_array(),
            pad1: 0.0,
            ambient: light.ambient.to_array(),
            sky: light.sky,
            shadow_texel: 1.0 / shadow_size,
            shadow_normal_offset: extent / shadow_size * 1.5,
            shadow_depth_bias: 0.0005,
            pad2: 0.0,
        };
        self.views.write(&self.shared.queue, &main, light_vp.to_cols_array_2d(), &data.wind);
        if let Some(w) = data.water.first() {
            self.water.write(&self.shared.queue, &main, &data.camera, (self.width, self.height), options.water_output, w.height);
        }
        let mut stats = FrameStats { instances: self.trees.instance_count, ..Default::default() };

        if let Some(t) = &mut self.timer {
            t.begin_frame();
        }
        // 3. Compute: the grass blades are culled into this frame's draw lists.
        self.grass.compute(encoder, self.timer.as_mut());
        // 4. Shadow. The pass always runs, so the map is cleared even when nothing casts.
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shadow pass"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.lighting.shadow_view,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: self.timer.as_mut().and_then(|t| t.scope("shadow")),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            if key.shadows {
                let sun = key.with_view(ViewKind::Sun);
                pass.set_bind_group(0, &self.views.sun.bind_group, &[]);
                self.trees.draw_depth(&mut pass, sun)?;
                if let Some(c) = &self.canopy {
                    c.draw_depth(&mut pass, sun)?;
                }
            }
        }

        // 4b. Water views: what the water reflects and what lies below it, drawn with the main
        // view's pipelines from the water's own views. Their draws are not the main pass's.
        let mut water_stats = FrameStats::default();
        for w in self.water.passes() {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(w.label),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: w.color,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::BLACK), store: wgpu::StoreOp::Store },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: w.depth,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: self.timer.as_mut().and_then(|t| t.scope(w.label)),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, w.view, &[]);
            pass.set_bind_group(1, &self.lighting.bind_group, &[]);
            let s = &mut water_stats;
            self.trees.draw(Phase::Opaque, &mut pass, key, s)?;
            self.trees.draw(Phase::AlphaClipped, &mut pass, key, s)?;
            self.ground.draw(Phase::Opaque, &mut pass, key, s)?;
            if w.sky {
                self.sky.draw(Phase::Sky, &mut pass, key, s)?;
            }
        }

        // 5. Main.
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("main pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Clear(self.options.clear), store: wgpu::StoreOp::Store },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.depth,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                    stencil_ops: None,
                }),
                timestamp_writes: self.timer.as_mut().and_then(|t| t.scope("main")),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &self.views.main.bind_group, &[]);
            pass.set_bind_group(1, &self.lighting.bind_group, &[]);
            let s = &mut stats;
            // Opaque, trees first and the ground after the trees' alpha-clipped leaves: on a
            // software rasteriser the early depth test then skips most hidden ground fragments.
            self.trees.draw(Phase::Opaque, &mut pass, key, s)?;
            self.trees.draw(Phase::AlphaClipped, &mut pass, key, s)?;
            if let Some(c) = &self.canopy {
                c.draw(Phase::AlphaClipped, &mut pass, key, s)?;
            }
            // The photograph before the ground, which it hides where it lies.
            if let Some(a) = &self.aerial_ground {
                a.draw(Phase::Opaque, &mut pass, key, s)?;
            }
            // Water before the ground, for the same reason: the bed under it is then skipped.
            // The ground still hides the parts of the outline that lie above the shore.
            self.water.draw(Phase::Opaque, &mut pass, key, s)?;
            self.ground.draw(Phase::Opaque, &mut pass, key, s)?;
            self.grass.draw(Phase::Opaque, &mut pass, key, s)?;
            // The sky where nothing was drawn.
            self.sky.draw(Phase::Sky, &mut pass, key, s)?;
            // Blended: no feature yet (the aerial canopy is alpha-clipped, drawn after the trees).
            if options.overlay {
                self.overlay.draw(Phase::Overlay, &mut pass, key, s)?;
            }
        }

        // 6. Resolve the timestamps.
        if let Some(t) = &mut self.timer {
            t.resolve(encoder);
        }
        self.stats = stats;
        Ok(())
    }
}

/// The box around both boxes, or either.
fn union(a: Option<(Vec3, Vec3)>, b: Option<(Vec3, Vec3)>) -> Option<(Vec3, Vec3)> {
    match (a, b) {
        (Some((a0, a1)), Some((b0, b1))) => Some((a0.min(b0), a1.max(b1))),
        (a, None) => a,
        (None, b) => b,
    }
}
