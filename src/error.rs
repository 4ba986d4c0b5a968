//! The app library's one error type: every error a `grove` library function returns converts
//! into [`Error`] with `?`, its one-line message unchanged, for a caller that wants a single
//! type (the specific types stay for callers that match on what went wrong). The CLI prints
//! any of them as one line on stderr.

use crate::aerial::AerialError;
use crate::bank::BankError;
use crate::bench::BenchError;
use crate::html::HtmlError;
use crate::lsystem::expr::ExprError;
use crate::lsystem::LsystemError;
use crate::render::trees::impostor::cache::AtlasError;
use crate::render::overlay::controller::ControllerError;
use crate::models::GltfError;
use crate::render::{ClipmapError, PipelineError, RenderError};
use crate::serve::ServeError;
use crate::species::SpeciesError;
use crate::study::{ShardError, StudyError, SynthError};
use crate::atomic_write::WriteError;
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
    /// [`StudyError`].
    #[error(transparent)]
    Study(#[from] StudyError),
    /// [`ProtocolError`].
    #[error(transparent)]
    Protocol(#[from] crate::protocol::ProtocolError),
    /// [`ShardError`].
    #[error(transparent)]
    Shard(#[from] ShardError),
    /// [`SynthError`].
    #[error(transparent)]
    Synth(#[from] SynthError),
    /// [`WriteError`].
    #[error(transparent)]
    Write(#[from] WriteError),
    /// [`BenchError`].
    #[error(transparent)]
    Bench(#[from] BenchError),
    /// [`ServeError`].
    #[error(transparent)]
    Serve(#[from] ServeError),
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
        fn recordings(dir: &std::path::Path) -> Result<Vec<std::path::PathBuf>, Error> {
            Ok(crate::study::recordings_in(dir)?)
        }
        let e = recordings(std::path::Path::new("/nonexistent/replays")).unwrap_err();
        assert!(matches!(e, Error::Study(crate::study::StudyError::NoSuchFolder(_))), "{e:?}");
        assert_eq!(e.to_string(), "/nonexistent/replays: no such folder");
        fn part(bytes: &[u8]) -> Result<crate::study::shard::Partial, Error> {
            Ok(crate::study::shard::Partial::decode(bytes, "p.part")?)
        }
        assert!(matches!(part(b"x").unwrap_err(), Error::Shard(crate::study::ShardError::NotAPartial(_))));
        fn endpoint(url: &str) -> Result<crate::serve::client::conn::Endpoint, Error> {
            Ok(crate::serve::client::conn::Endpoint::parse(url, None).map_err(crate::serve::ServeError::from)?)
        }
        let e = endpoint("ftp://lab/").err().expect("refused");
        assert!(matches!(e, Error::Serve(crate::serve::ServeError::Client(_))), "{e:?}");
        assert_eq!(e.to_string(), "--to \"ftp://lab/\": the URL must start with http:// or https://");
    }
}
