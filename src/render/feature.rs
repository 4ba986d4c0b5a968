//! What the frame ([`super::frame`]) and its drawn features share: the frame-wide extract
//! ([`Common`]), the views computed before prepare ([`FrameViews`]), what each stage hands a
//! feature, the phases of the main pass, the draw statistics and the [`Feature`] trait.
//!
//! A leaf of `src/render`: it names no feature module, so features import their frame types
//! from here and never from the renderer above them.

use glam::{Mat4, Vec3};
use grove_systems::Sim;
use grove_systems::wind_model::{WindModel, WindParams};

use super::error::RenderError;
use super::gpu::{PipelineKey, Shared};
use super::options::RenderOptions;
use super::view::{Camera, ViewUniform};

/// Draw statistics of the last frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameStats {
    /// Tree instances drawn (the main view's).
    pub instances: usize,
    /// Tree instances drawn into the shadow map (0 without shadows).
    pub shadow_instances: usize,
    /// Draw calls in the main pass.
    pub draws: usize,
    /// Triangles submitted in the main pass.
    pub triangles: usize,
}

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

/// What every feature may read of the frame, copied out of the world once by the frame's own
/// extract ([`super::extract::common`]): the camera drawn from, the sun, the time and the wind.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Common {
    /// The camera drawn from: the head's, or the options' override (a top view's perspective
    /// stand-in, a video's camera).
    pub camera: Camera,
    /// Unit vector towards the sun.
    pub sun_dir: Vec3,
    /// The sun's true elevation, degrees.
    pub sun_elevation_deg: f64,
    /// Simulated time, seconds.
    pub time: f64,
    /// The per-vertex wind parameters of this frame.
    pub wind: WindParams,
    /// The global wind model (a pipeline choice).
    pub wind_model: WindModel,
}

/// What a feature's [`Feature::extract`] sees besides the world.
pub(crate) struct ExtractContext<'a> {
    /// The frame's common data.
    pub common: &'a Common,
    /// The renderer's options.
    pub options: &'a RenderOptions,
    /// The target's size, pixels.
    pub size: (u32, u32),
    /// Whether the canopy draws the photographed crowns this frame (then the trees leave their
    /// models out); without it they are trees like the others.
    pub canopy: bool,
}

/// The frame's views, computed before prepare from the extracted data: the main camera's
/// uniforms (what group 0 holds, with the sun's matrix fitted to what the features draw).
pub(crate) struct FrameViews {
    /// The main view's uniforms.
    pub main: ViewUniform,
    /// The camera's perspective view-projection matrix (also with a top view, whose
    /// orthographic matrix is in `main`): what culling and levels of detail use.
    pub camera_view_proj: Mat4,
}

/// What a feature's [`Feature::prepare`] sees of the frame.
pub(crate) struct FrameContext<'a> {
    /// The device, queue and shared layouts.
    pub shared: &'a Shared,
    /// The frame's common data.
    pub common: &'a Common,
    /// The frame's views.
    pub views: &'a FrameViews,
    /// The main view's pipeline key; a feature that casts shadows also prepares the sun's
    /// (`key.with_view(ViewKind::Sun)`) when `key.shadows` is set.
    pub key: PipelineKey,
    /// The target's size, pixels.
    pub size: (u32, u32),
    /// The renderer's options.
    pub options: &'a RenderOptions,
}

/// The interface between the frame and a drawn feature. A feature owns its extract: it copies
/// what it draws out of the read-only world into its own [`Feature::Extracted`] type, and that
/// copy is all its prepare sees of the world.
pub(crate) trait Feature {
    /// What the feature copies out of the world each frame.
    type Extracted;

    /// Copies this frame's data out of the world (read only). A feature may compare with what
    /// it already has and copy only what changed.
    fn extract(&self, sim: &Sim, cx: &ExtractContext<'_>) -> Self::Extracted;

    /// Whether the extracted data casts a shadow (the frame draws the shadow map only then).
    fn casts_shadows(&self, _data: &Self::Extracted) -> bool {
        false
    }

    /// The box the sun's view must cover for this feature, metres; `None` for nothing.
    fn shadow_bounds(&self, _data: &Self::Extracted) -> Option<(Vec3, Vec3)> {
        None
    }

    /// Uploads this frame's data and builds the pipelines of `cx.key` on first use. Fails for
    /// a key the feature has no pipeline for.
    fn prepare(&mut self, cx: &FrameContext<'_>, data: Self::Extracted) -> Result<(), RenderError>;

    /// Draws depth only from the sun into the shadow map (shadow casters only), with the
    /// pipelines of `key` (the sun's view).
    fn draw_depth<'p>(&'p self, _pass: &mut wgpu::RenderPass<'p>, _key: PipelineKey) -> Result<(), RenderError> {
        Ok(())
    }

    /// Draws the feature's part of `phase` in the main pass, with the pipelines of `key`. The
    /// frame has bound group 0 (the view) and group 1 (the lighting); a feature binds group 2.
    fn draw<'p>(
        &'p self,
        phase: Phase,
        pass: &mut wgpu::RenderPass<'p>,
        key: PipelineKey,
        stats: &mut FrameStats,
    ) -> Result<(), RenderError>;
}

/// The box around both boxes, or either.
pub(crate) fn union(a: Option<(Vec3, Vec3)>, b: Option<(Vec3, Vec3)>) -> Option<(Vec3, Vec3)> {
    match (a, b) {
        (Some((a0, a1)), Some((b0, b1))) => Some((a0.min(b0), a1.max(b1))),
        (a, None) => a,
        (None, b) => b,
    }
}
