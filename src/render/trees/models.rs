//! The trees feature's own methods: models uploaded for a catalogue id, the impostor cache, and
//! what is loaded (`renderer.features.trees`).

use std::path::PathBuf;

use grove_systems::catalogue::ModelId;

use super::Trees;
use super::model::GpuModel;
use crate::models::ModelData;

impl Trees {
    /// Uploads a model and uses it for trees of `id`, replacing any previous one.
    pub fn set_model(&mut self, id: ModelId, data: &ModelData) {
        let mut model = GpuModel::upload(&self.shared, data);
        self.bake_impostor(&mut model, data);
        let idx = usize::from(id.0);
        if self.models.len() <= idx {
            self.models.resize_with(idx + 1, || None);
        }
        self.models[idx] = Some(model);
    }

    /// Draws trees of `id` as model `far` where they are small on screen
    /// ([`crate::render::RenderOptions::far_pixels`]); `None` draws model `id` at every size.
    pub fn set_far(&mut self, id: ModelId, far: Option<ModelId>) {
        let idx = usize::from(id.0);
        if self.far.len() <= idx {
            self.far.resize(idx + 1, None);
        }
        self.far[idx] = far.map(|f| usize::from(f.0));
    }

    /// Sets the folder of the impostor atlas cache for models loaded from now on (`None`: bake
    /// every model). The default comes from the environment (`trees::impostor::cache`).
    pub fn set_impostor_cache(&mut self, dir: Option<PathBuf>) {
        self.impostor_cache = dir;
    }

    /// How many impostor atlases this renderer baked (the others were read from the cache).
    pub fn impostor_bakes(&self) -> usize {
        self.impostor_bakes
    }

    /// The model drawn for `id`, if one is loaded.
    pub fn model(&self, id: ModelId) -> Option<&GpuModel> {
        self.models.get(usize::from(id.0)).and_then(|m| m.as_ref())
    }

    /// The names of the loaded models, by id (empty where none).
    pub fn model_names(&self) -> Vec<String> {
        self.models.iter().map(|m| m.as_ref().map(|m| m.name.clone()).unwrap_or_default()).collect()
    }
}
