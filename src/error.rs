//! The app library's one error type: every error a `grove` library function returns converts
//! into [`Error`] with `?`, its one-line message unchanged, for a caller that wants a single
//! type (the specific types stay for callers that match on what went wrong). The CLI prints
//! any of them as one line on stderr.

use crate::aerial::AerialError;
use crate::bank::BankError;
use crate::html::HtmlError;
use crate::lsystem::expr::ExprError;
use crate::lsystem::LsystemError;
use crate::render::trees::impostor::cache::AtlasError;
use crate::render::overlay::controller::ControllerError;
use crate::models::GltfError;
use crate::render::{ClipmapError, PipelineError, RenderError};
use crate::species::SpeciesError;
use crate::video::encode::VideoError;
use crate::video::ghosts::GhostError;
use crate::video::MarkError;

/// Any error of the `grove` library, or of grove-systems beneath it.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// [`grove_systems::Error`].
    #[error(transparent)]
    Systems(#[from] grove_systems::Error),
    /// [`AerialError`].
    #[error(transparent)]
    Aerial(#[from] AerialError),
    /// [`BankError`].
    #[error(transparent)]
    Bank(#[from] BankError),
    /// [`HtmlError`].
    #[error(transparent)]
    Html(#[from] HtmlError),
    /// [`ExprError`].
    #[error(transparent)]
    Expr(#[from] ExprError),
    /// [`LsystemError`].
    #[error(transparent)]
    Lsystem(#[from] LsystemError),
    /// [`RenderError`].
    #[error(transparent)]
    Render(#[from] RenderError),
    /// [`PipelineError`].
    #[error(transparent)]
    Pipeline(#[from] PipelineError),
    /// [`ClipmapError`].
    #[error(transparent)]
    Clipmap(#[from] ClipmapError),
    /// [`GltfError`].
    #[error(transparent)]
    Gltf(#[from] GltfError),
    /// [`AtlasError`].
    #[error(transparent)]
    Atlas(#[from] AtlasError),
    /// [`ControllerError`].
    #[error(transparent)]
    Controller(#[from] ControllerError),
    /// [`VideoError`].
    #[error(transparent)]
    Video(#[from] VideoError),
    /// [`GhostError`].
    #[error(transparent)]
    Ghost(#[from] GhostError),
    /// [`MarkError`].
    #[error(transparent)]
    Mark(#[from] MarkError),
    /// [`SpeciesError`].
    #[error(transparent)]
    Species(#[from] SpeciesError),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_of_both_crates_convert_with_their_messages_unchanged() {
        let path = std::path::Path::new("/nonexistent/scene.ron");
        fn scene(path: &std::path::Path) -> Result<grove_systems::scene::Scene, Error> {
            Ok(grove_systems::scene::Scene::load(path).map_err(grove_systems::Error::from)?)
        }
        let e = scene(path).unwrap_err();
        assert!(matches!(e, Error::Systems(_)));
        assert_eq!(e.to_string(), grove_systems::scene::Scene::load(path).unwrap_err().to_string());
        fn gltf(path: &std::path::Path) -> Result<crate::models::ModelData, Error> {
            Ok(crate::models::load_model(path)?)
        }
        let e = gltf(std::path::Path::new("/nonexistent/model.gltf")).unwrap_err();
        assert!(e.to_string().contains("model.gltf"), "{e}");
    }
}
