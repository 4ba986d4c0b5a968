//! [`PipelineKey`]: what a pipeline is specialised for, and [`ViewKind`], the camera a pass
//! draws from. A leaf of `src/render` (re-exported by [`super::gpu`]), so that the renderer's
//! error type ([`super::error`]) can name a key without importing the device module.

use grove_systems::wind_model::WindModel;

/// The camera a pass draws from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ViewKind {
    /// The head's camera: the main pass.
    Main,
    /// The sun: the shadow map, depth only.
    Sun,
}

/// What a pipeline is specialised for: the frame-wide choices compiled into its shaders as WGSL
/// `override` constants, the target format and the view.
///
/// Lavapipe runs both sides of a branch, even one on a uniform value, so a shader that checks a
/// uniform to skip work pays for that work anyway. The choices that hold for a whole frame are
/// therefore compiled in: `SHADOWS` (lighting.wgsl: whether lit shaders look up the shadow map)
/// and `WIND_MODEL` (trees/trees.wgsl). Each feature builds the pipelines of a key on first use
/// and refuses a key it has no pipeline for (see `PipelineCache` in [`super::gpu`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PipelineKey {
    /// Whether lit shaders sample the shadow map.
    pub shadows: bool,
    /// The global wind model.
    pub wind: WindModel,
    /// The colour target's format.
    pub format: wgpu::TextureFormat,
    /// The view drawn from.
    pub view: ViewKind,
}

impl PipelineKey {
    /// The same key for another view.
    pub fn with_view(self, view: ViewKind) -> PipelineKey {
        PipelineKey { view, ..self }
    }

    /// The `override` constant of lit shaders (lighting.wgsl is prepended to each).
    pub fn lit_constants(self) -> [(&'static str, f64); 1] {
        [("SHADOWS", if self.shadows { 1.0 } else { 0.0 })]
    }

    /// The `override` constants of the tree shaders. The wind model's code is the one the
    /// simulation's `WindParams::model` carries.
    pub fn tree_constants(self) -> [(&'static str, f64); 2] {
        let [lit] = self.lit_constants();
        [lit, ("WIND_MODEL", f64::from(self.wind.code()))]
    }
}
