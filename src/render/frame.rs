//! The frame, in order, as `systems/src/schedule.rs` is for the simulation:
//!
//! 1. **Extract**: the frame's common data ([`super::extract::common`]: camera, sun, time,
//!    wind), then each feature copies its own part out of the world ([`Feature::extract`]).
//! 2. **Views**: the frame-wide choices (shadows on or off, the wind model: one
//!    [`PipelineKey`]), the main camera's uniforms and the sun's view fitted to what the
//!    features will draw ([`Feature::shadow_bounds`]).
//! 3. **Prepare**: each feature's buffers and pipelines from its extracted data
//!    ([`Feature::prepare`]); then the trees are culled for each pass: the main view, the water
//!    views and the shadow map (the trees whose shadows may fall into one of those).
//! 4. **Compute**: the grass blades are culled into draw lists and indirect draw counts.
//! 5. **Shadow**: depth from the sun of every shadow caster ([`Feature::draw_depth`]).
//!    **Water views** (only with water): the reflection (trees, ground, sky from the mirrored
//!    camera) and the refraction (trees and ground below the surface), at half resolution,
//!    each only where the surface can read it (a scissor around the ponds' outlines).
//! 6. **Main**: the phases in order ([`Phase`]): opaque, alpha-clipped, sky, blended, overlay.
//! 7. **Resolve** the pass timestamps.
//!
//! Features are named fields of [`super::Features`] called here in a visible order; there is no
//! render graph and no registry. A new feature is a folder with its module, its `extract.rs` and
//! its shader, one field and one line in each stage it takes part in (see ARCHITECTURE.md).

use grove_systems::Sim;

use super::error::RenderError;
use super::extract;
use super::feature::{union, ExtractContext, Feature, FrameContext, FrameStats, FrameViews, Phase};
use super::gpu::{PipelineKey, ViewKind};
use super::lighting::{light_matrix, shadow_bounds, sun_light};
use super::clip::ClipRegion;
use super::trees::TreeView;
use super::view::{camera_matrix, ViewUniform};
use super::Renderer;

impl Renderer {
    /// Records one frame of `sim` into `encoder`, drawing into `view`.
    pub(crate) fn encode_frame(&mut self, sim: &Sim, view: &wgpu::TextureView, encoder: &mut wgpu::CommandEncoder) -> Result<(), RenderError> {
        let options = self.options;
        let size = (self.width, self.height);
        let f = &mut self.features;

        // 1. Extract. Without a canopy the photographed crowns are trees like the others.
        let common = extract::common(sim, &options);
        let ecx = ExtractContext { common: &common, options: &options, size, canopy: f.aerial.canopy.is_some() && options.canopy };
        let trees = f.trees.extract(sim, &ecx);
        let ground = f.ground.extract(sim, &ecx);
        let grass = f.grass.extract(sim, &ecx);
        let sky = f.sky.extract(sim, &ecx);
        let overlay = f.overlay.extract(sim, &ecx);
        let water = f.water.extract(sim, &ecx);
        let aerial_ground = f.aerial.ground.as_ref().map(|a| a.extract(sim, &ecx));
        let canopy = f.aerial.canopy.as_ref().map(|c| c.extract(sim, &ecx));

        // 2. Views. Shadows are decided here and only here: asked for, the sun up, and
        // something to cast them.
        self.lighting.set_shadow_size(&self.shared, options.shadow_size);
        let light = sun_light(common.sun_elevation_deg);
        let casts = f.trees.casts_shadows(&trees) || f.aerial.canopy.as_ref().zip(canopy.as_ref()).is_some_and(|(c, x)| c.casts_shadows(x));
        let key = PipelineKey { shadows: options.shadows && light.direct.max_element() > 0.0 && casts, wind: common.wind_model, format: self.format, view: ViewKind::Main };
        // The sun's view covers the trees, the planes and the canopy within 80 m of the camera.
        let canopy_bounds = f.aerial.canopy.as_ref().zip(canopy.as_ref()).and_then(|(c, x)| c.shadow_bounds(x));
        let drawn = union(union(f.trees.shadow_bounds(&trees), f.ground.shadow_bounds(&ground)), canopy_bounds);
        let camera_view_proj = camera_matrix(&common.camera, self.width as f32 / self.height as f32);
        let view_proj = options.top_view.map_or(camera_view_proj, |top| top.matrix());
        let (smin, smax) = shadow_bounds(drawn, common.camera.position);
        let (light_vp, extent) = light_matrix(common.sun_dir, smin, smax);
        let shadow_size = self.lighting.shadow_size as f32;
        let main = ViewUniform {
            view_proj: view_proj.to_cols_array_2d(),
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            light_view_proj: light_vp.to_cols_array_2d(),
            camera_pos: common.camera.position.to_array(),
            time: (common.time % 3600.0) as f32,
            sun_dir: common.sun_dir.to_array(),
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
        self.views.write(&self.shared.queue, &main, light_vp.to_cols_array_2d(), &common.wind);
        let views = FrameViews { main, camera_view_proj };

        // 3. Prepare.
        let cx = FrameContext { shared: &self.shared, common: &common, views: &views, key, size, options: &options };
        f.trees.prepare(&cx, trees)?;
        f.ground.prepare(&cx, ground)?;
        f.grass.prepare(&cx, grass)?;
        f.sky.prepare(&cx, sky)?;
        f.overlay.prepare(&cx, overlay)?;
        f.water.prepare(&cx, water)?;
        if let (Some(a), Some(x)) = (&mut f.aerial.ground, aerial_ground) {
            a.prepare(&cx, x)?;
        }
        if let (Some(c), Some(x)) = (&mut f.aerial.canopy, canopy) {
            c.prepare(&cx, x)?;
        }
        // The trees each pass draws: those that may reach into its view, and for the shadow
        // map those within the sun's view (`light`) whose shadows may reach into one (down to
        // the lowest drawn point, less a metre).
        let sun = key.shadows.then(|| drawn.map(|(lo, _)| (common.sun_dir, lo.y - 1.0))).flatten();
        let light = ClipRegion::new(light_vp);
        f.trees.cull(&ClipRegion::new(view_proj), f.water.regions(), sun, &light, shadow_size / extent.max(1e-3), options.cull_trees);
        let f = &self.features;
        let shadow_instances = if key.shadows { f.trees.shadow_instance_count } else { 0 };
        let mut stats = FrameStats { instances: f.trees.instance_count, shadow_instances, ..Default::default() };

        if let Some(t) = &mut self.timer {
            t.begin_frame();
        }
        // 4. Compute: the grass blades are culled into this frame's draw lists.
        f.grass.compute(encoder, self.timer.as_mut());
        // 5. Shadow. The pass always runs, so the map is cleared even when nothing casts.
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
                f.trees.draw_depth(&mut pass, sun)?;
                if let Some(c) = &f.aerial.canopy {
                    c.draw_depth(&mut pass, sun)?;
                }
            }
        }

        // 5b. Water views: what the water reflects and what lies below it, drawn with the main
        // view's pipelines from the water's own views. Their draws are not the main pass's.
        let mut water_stats = FrameStats::default();
        for (i, w) in f.water.passes().into_iter().enumerate() {
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
            if let Some([x, y, width, height]) = w.scissor {
                pass.set_scissor_rect(x, y, width, height);
            }
            pass.set_bind_group(0, w.view, &[]);
            pass.set_bind_group(1, &self.lighting.bind_group, &[]);
            let s = &mut water_stats;
            f.trees.draw_view(TreeView::Extra(i), Phase::Opaque, &mut pass, key, s)?;
            f.trees.draw_view(TreeView::Extra(i), Phase::AlphaClipped, &mut pass, key, s)?;
            f.ground.draw(Phase::Opaque, &mut pass, key, s)?;
            if w.sky {
                f.sky.draw(Phase::Sky, &mut pass, key, s)?;
            }
        }

        // 6. Main.
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
            f.trees.draw(Phase::Opaque, &mut pass, key, s)?;
            f.trees.draw(Phase::AlphaClipped, &mut pass, key, s)?;
            if let Some(c) = &f.aerial.canopy {
                c.draw(Phase::AlphaClipped, &mut pass, key, s)?;
            }
            // Without a background (a model's coverage alone), the trees are all there is.
            if options.background {
                // The photograph before the ground, which it hides where it lies.
                if let Some(a) = &f.aerial.ground {
                    a.draw(Phase::Opaque, &mut pass, key, s)?;
                }
                // Water before the ground, for the same reason: the bed under it is then
                // skipped. The ground still hides the parts of the outline that lie above the
                // shore.
                f.water.draw(Phase::Opaque, &mut pass, key, s)?;
                f.ground.draw(Phase::Opaque, &mut pass, key, s)?;
                f.grass.draw(Phase::Opaque, &mut pass, key, s)?;
                // The sky where nothing was drawn.
                f.sky.draw(Phase::Sky, &mut pass, key, s)?;
            }
            // Blended: no feature yet (the aerial canopy is alpha-clipped, drawn after the trees).
            if options.overlay {
                f.overlay.draw(Phase::Overlay, &mut pass, key, s)?;
            }
        }

        // 7. Resolve the timestamps.
        if let Some(t) = &mut self.timer {
            t.resolve(encoder);
        }
        self.stats = stats;
        Ok(())
    }
}
