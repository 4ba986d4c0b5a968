//! The renderer's options: what a frame draws and how, set by the caller between frames
//! ([`crate::render::Renderer::options`]). A leaf: it names no feature module.

use super::view::{Camera, TopView};

/// What the water surface shows: normally the water; the reflection or the refraction alone for
/// tests and for looking at one of them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum WaterOutput {
    /// Reflection and refraction mixed by Fresnel, with glint and shore.
    #[default]
    Full,
    /// The reflection texture as the surface looks it up (ripples included).
    Reflection,
    /// The refraction texture as the surface looks it up.
    Refraction,
}

/// The default on-screen size, pixels, below which trees are impostors
/// ([`RenderOptions::impostor_pixels`]).
pub const DEFAULT_IMPOSTOR_PIXELS: f32 = 150.0;

/// The on-screen size, in pixels, of a tree's bounding sphere below which a model with a far
/// model is drawn as that model ([`RenderOptions::far_pixels`]): the shipped species' level of
/// detail 2 (about a fifth of level 1's triangles) stands in for level 1 below it.
pub const DEFAULT_FAR_PIXELS: f32 = 400.0;

/// Rendering options.
#[derive(Clone, Copy, Debug)]
pub struct RenderOptions {
    /// Draw the sun's shadow map.
    pub shadows: bool,
    /// Shadow-map edge, texels; clamped to [`crate::render::lighting::SHADOW_SIZES`] (see
    /// [`crate::render::Renderer::shadow_size`]).
    pub shadow_size: u32,
    /// Background colour where there is no sky (linear RGBA); the sky normally covers it.
    pub clear: wgpu::Color,
    /// The smallest area, in pixels, a drawn leaf should cover: farther trees draw a share of
    /// their leaves, grown to keep the crown's area ([`crate::render::lod`]). 0 draws every leaf.
    pub leaf_pixels: f32,
    /// Draw the scene's water (its reflection and refraction passes and the surface).
    pub water: bool,
    /// What the water surface shows (normally the water itself).
    pub water_output: WaterOutput,
    /// Draw the scene's grass patches (`--no-grass` turns them off).
    pub grass: bool,
    /// Bend grass blades away from the eye and the controller's hit point when they are near.
    pub grass_bend: bool,
    /// Draw the interaction visuals (the controller's ray, the hit marker, the anchor ball, the
    /// selection and the task's targets).
    pub overlay: bool,
    /// The on-screen size, in pixels, of a tree's bounding sphere below which it is drawn as an
    /// impostor (with a cross-fade up to [`crate::render::trees::impostor::BAND`] times as many). 0 draws
    /// every tree as a mesh. The default, [`DEFAULT_IMPOSTOR_PIXELS`], keeps the reference
    /// scene's image within a mean absolute error of 4 of 255 per channel of the full-detail
    /// render (README, `grove bench render-reference`).
    pub impostor_pixels: f32,
    /// The on-screen size, in pixels, of a tree's bounding sphere below which a model with a
    /// far model (a coarser level of detail of the same tree, `BankModel::far`) is drawn as that
    /// model. 0 always draws the model itself. The default is [`DEFAULT_FAR_PIXELS`].
    pub far_pixels: f32,
    /// Cross-fade between a tree's levels of detail with a screen-door dither: its model and its
    /// far model over [`crate::render::trees::instances::FAR_BAND`], its mesh and its impostor
    /// over [`crate::render::trees::impostor::BAND`], in the shadow map too. Off, each level
    /// gives way to the next at once (for showing the pop the cross-fade removes).
    pub lod_cross_fade: bool,
    /// Fade a blade lawn into the ground along its edge (`grass/edges.rs`): fewer and shorter
    /// blades towards the edge. Off, the blades stand as the simulation places them, up to a hard
    /// edge (for comparing with images drawn before the fade). Read when the grass is built.
    pub blade_edge_fade: bool,
    /// Draw the photographed crowns as canopy layers (with aerial photographs set by
    /// [`crate::render::AerialPhotos::set`]); off, or without layer masks, they are drawn as tree models.
    pub canopy: bool,
    /// Draw from straight above with an orthographic projection ([`TopView`]) instead of
    /// the world's head camera.
    pub top_view: Option<TopView>,
    /// Draw from this camera instead of the world's head camera (a video's shoulder or orbit
    /// camera); the head is then drawn as a figure like the ghosts.
    pub camera: Option<Camera>,
    /// Draw the world's background: the sky, the ground, grass, water and the aerial
    /// photograph. Off (`grove render --model FILE --background transparent`), a frame holds
    /// the trees alone on [`RenderOptions::clear`] (transparent there), so a pixel's alpha is the
    /// trees' coverage; the shadow map and the light are those of the frame with its background.
    pub background: bool,
    /// Skip the trees a pass cannot show: those wholly outside its view, and in the shadow map
    /// those whose shadows cannot fall into a view (`trees::Trees::cull`). Culling changes no
    /// pixel; off, every pass draws every tree (for comparing the two).
    pub cull_trees: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions { shadows: true, shadow_size: 1024, clear: wgpu::Color::BLACK, leaf_pixels: 32.0, water: true, water_output: WaterOutput::Full, grass: true, grass_bend: true, overlay: true, impostor_pixels: DEFAULT_IMPOSTOR_PIXELS, far_pixels: DEFAULT_FAR_PIXELS, lod_cross_fade: true, blade_edge_fade: true, canopy: true, top_view: None, camera: None, background: true, cull_trees: true }
    }
}

