//! What a new simulation is made from: the options JavaScript hands over as JSON ([`Options`]),
//! turned into a recording header and its scene ([`Start`]).

use grove_systems::replay::{FORMAT_VERSION, Header, Line, SessionFields, decode_line};
use grove_systems::scene::Scene;
use grove_systems::set_arg::{SetArg, SetArgs};
use serde::Deserialize;

use crate::error::Error;

/// The options of a new simulation. Either the fields of a new recording (`scene`, `seed`,
/// `set`, …), or `header`: a recording's header line made elsewhere (a session server), which
/// the simulation then follows, its recorder continuing the checksum chain after it.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Options {
    /// A built-in scene's name ("study"), or the name of the scene file whose text `scene_text`
    /// holds (a recording's header names it; a native replay looks for it next to the recording).
    pub scene: Option<String>,
    /// The scene file's text, for a scene that is not built in.
    pub scene_text: Option<String>,
    /// The RNG seed; the scene's own seed by default.
    pub seed: Option<u64>,
    /// Parameter overrides, each `NAME=VALUE` as `grove … --set` takes them.
    #[serde(default)]
    pub set: Vec<String>,
    /// Make a recording: its header line is the first line handed back.
    #[serde(default)]
    pub record: bool,
    /// A recording's header line made elsewhere: the simulation is the one it describes, and
    /// its recorder writes the lines after it.
    pub header: Option<String>,
    /// The study task the session runs (its id, e.g. "ray-casting-7"), for the header.
    pub task: Option<String>,
    /// The participant's id, for the header.
    pub participant: Option<String>,
    /// Whether the session is generated rather than a person's.
    #[serde(default)]
    pub synthetic: bool,
    /// The wall-clock start of the session (RFC 3339), for the header.
    pub session_start: Option<String>,
    /// The 1-based block of the participant's session, for the header.
    pub block: Option<u32>,
    /// A registered technique to switch to at the first tick (a plug-in's name goes into the
    /// header, as `grove play --technique` writes it).
    pub technique: Option<String>,
    /// The staging scene that shows one model alone, as `grove render --model` frames it
    /// (`grove_systems::stage`), instead of a scene: nothing else may be given with it, and it
    /// records nothing.
    pub stage: Option<StageOptions>,
}

/// The model stage's options: the model's bounds (model space, metres), the image's aspect
/// ratio, whether the study's wind blows (`grove render --model FILE --tick T`), and a walker's
/// view from a distance in place of the framing of the bounds.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StageOptions {
    /// The model's lowest corner, metres.
    pub min: [f32; 3],
    /// The model's highest corner, metres.
    pub max: [f32; 3],
    /// Width over height of the image the stage is framed for.
    pub aspect: f32,
    /// Put the study scene's wind on the stage (`grove_systems::stage::in_study_wind`).
    #[serde(default)]
    pub wind: bool,
    /// A walker's view from this many metres (`grove_systems::stage::walker_view`: eye height,
    /// looking at 45 % of the model's top, the sheet of docs/species.md), not the framing of the
    /// bounds.
    #[serde(default)]
    pub from: Option<f32>,
}

/// The largest model a stage shows, metres along any axis (a catalogue model is under 40 m).
pub const MAX_STAGE_SIZE: f32 = 1000.0;

impl StageOptions {
    /// The stage's simulation; bounds that are not finite, not ordered or larger than
    /// [`MAX_STAGE_SIZE`], or an aspect outside 0.01..100, are refused.
    pub fn sim(&self) -> Result<grove_systems::Sim, Error> {
        let (min, max) = (glam::Vec3::from(self.min), glam::Vec3::from(self.max));
        let refuse = |m: String| Error::input("stage", m);
        if !(min.is_finite() && max.is_finite())
            || min.cmpgt(max).any()
            || (max - min).max_element() > MAX_STAGE_SIZE
            || min.abs().max_element() > MAX_STAGE_SIZE
        {
            return Err(refuse(format!(
                "bounds {:?}..{:?} must be finite, ordered and within {MAX_STAGE_SIZE} m",
                self.min, self.max
            )));
        }
        if !(self.aspect.is_finite() && (0.01..=100.0).contains(&self.aspect)) {
            return Err(refuse(format!("aspect {} must be between 0.01 and 100", self.aspect)));
        }
        if let Some(d) = self.from
            && !(d.is_finite() && (0.1..=MAX_STAGE_SIZE).contains(&d))
        {
            return Err(refuse(format!("from {d} must be between 0.1 and {MAX_STAGE_SIZE} m")));
        }
        let model = grove_systems::catalogue::ModelId(0);
        let mut sim = grove_systems::stage::model_stage((min, max), self.aspect, false, model)
            .map_err(|e| refuse(e.to_string()))?;
        if self.wind {
            grove_systems::stage::in_study_wind(&mut sim).map_err(|e| refuse(e.to_string()))?;
        }
        if let Some(d) = self.from {
            grove_systems::stage::walker_view(&mut sim, max.y, d);
        }
        Ok(sim)
    }
}

/// A simulation about to be built: its header, its scene, whether the header line is the
/// caller's (so the recorder continues after it), and the technique to switch to first.
pub struct Start {
    /// The recording's header.
    pub header: Header,
    /// The scene the header names.
    pub scene: Scene,
    /// The header line came from the caller.
    pub given_header: bool,
    /// A technique to switch to at tick 0.
    pub technique: Option<String>,
}

/// The scene a name (and optional text) stands for: a built-in one, or the text, which must be
/// self-contained (grove-systems' `scene_text` rule, the one `grove serve` keeps too: the module
/// has no file system).
pub fn scene(name: &str, text: Option<&str>) -> Result<Scene, Error> {
    let refuse = |message: String| Error::Scene { name: name.to_string(), message };
    let Some(text) = text else {
        return Scene::builtin(name)
            .ok_or_else(|| refuse("not a built-in scene (\"study\"); hand over its text as scene_text".into()));
    };
    grove_systems::scene_text::self_contained(text).map_err(|e| refuse(e.to_string()))
}

impl Options {
    /// Reads the options from JSON.
    pub fn parse(json: &str) -> Result<Options, Error> {
        serde_json::from_str(json).map_err(|e| Error::input("options", e))
    }

    /// The header and scene these options describe.
    pub fn start(self) -> Result<Start, Error> {
        match self.header.clone() {
            Some(line) => self.following(&line),
            None => self.new_header(),
        }
    }

    fn following(self, line: &str) -> Result<Start, Error> {
        let fields = [
            ("scene", self.scene.is_some()),
            ("seed", self.seed.is_some()),
            ("set", !self.set.is_empty()),
            ("record", self.record),
            ("task", self.task.is_some()),
            ("participant", self.participant.is_some()),
            ("synthetic", self.synthetic),
            ("session_start", self.session_start.is_some()),
            ("block", self.block.is_some()),
            ("technique", self.technique.is_some()),
        ];
        if let Some((name, _)) = fields.iter().find(|(_, given)| *given) {
            return Err(Error::input("options", format!("`{name}` is given with `header`: the header line says it")));
        }
        let header = match decode_line(line.trim_end_matches(['\r', '\n'])) {
            Ok(Line::Header(h)) => h,
            Ok(_) => return Err(Error::HeaderLine("not a header line".into())),
            Err(e) => return Err(Error::HeaderLine(e.to_string())),
        };
        if header.format_version != FORMAT_VERSION {
            return Err(Error::HeaderLine(format!(
                "format version {} (the recorder continues version {FORMAT_VERSION})",
                header.format_version
            )));
        }
        let scene = scene(&header.scene, self.scene_text.as_deref())?;
        Ok(Start { header, scene, given_header: true, technique: None })
    }

    fn new_header(self) -> Result<Start, Error> {
        let name = self.scene.clone().unwrap_or_else(|| "study".into());
        let scene = scene(&name, self.scene_text.as_deref())?;
        let set = self.set.iter().map(|a| a.parse::<SetArg>()).collect::<Result<Vec<_>, _>>()?;
        let fields = SessionFields {
            participant: self.participant,
            task: self.task,
            block: self.block,
            session_start: self.session_start,
            technique: self.technique.clone(),
            synthetic: self.synthetic,
            config: SetArgs::single_values(&set)?.into_iter().collect(),
        };
        let header =
            fields.header(&name, self.seed.unwrap_or(scene.seed), scene.dt).map_err(|e| Error::input("options", e))?;
        Ok(Start { header, scene, given_header: false, technique: self.technique })
    }
}
