//! The app's interaction techniques: the two built-in ones and the plug-ins in [`plugins`].
//! Registering a plug-in is one line in that list (`docs/techniques.md`).

use grove_systems::technique::{Technique, TechniqueError, Techniques, install};

/// The plug-in techniques, in the order menus and reports list them after the built-in two.
pub fn plugins() -> Vec<Technique> {
    vec![grove_gaze_dwell::technique()]
}

/// Registers every technique for the simulations this process builds. Called once, first thing.
pub fn install_all() -> Result<(), TechniqueError> {
    install(Techniques::with(plugins())?)
}
