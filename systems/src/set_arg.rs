//! What `--set` takes, parsed once: `NAME=VALUE`, or `NAME=VALUE,VALUE…` for a sweep, each value
//! a checked [`Override`] of a parameter of [`Config::PARAMS`]. The command line (`grove study`,
//! `grove synth`, `grove test`), a study's shard header and any other caller read the same text
//! through [`SetArg`]'s `FromStr`, and put a run's arguments together with [`SetArgs`].

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::resources::{Config, ConfigError, Override, Param};

/// One `--set NAME=VALUE[,VALUE…]`: a known parameter and one or more checked values.
#[derive(Clone, Debug, PartialEq)]
pub struct SetArg {
    /// The parameter.
    pub param: &'static Param,
    /// Its values, in the order written (more than one: a sweep).
    pub values: Vec<Override>,
}

impl FromStr for SetArg {
    type Err = ConfigError;

    /// The one place `NAME=VALUE[,VALUE…]` is read: the name must be one of
    /// [`Config::NAMES`] and every value a number within its range ([`Override::new`]).
    fn from_str(arg: &str) -> Result<SetArg, ConfigError> {
        let (name, list) = arg.split_once('=').ok_or_else(|| ConfigError::NotNameValue(arg.to_string()))?;
        let texts: Vec<&str> = list.split(',').collect();
        if texts.len() > 1 && texts.iter().any(|t| t.trim().is_empty()) {
            return Err(ConfigError::EmptyValue(arg.to_string()));
        }
        let values = texts.iter().map(|t| Override::new(name, t)).collect::<Result<Vec<_>, _>>()?;
        let param =
            Param::named(values[0].name).ok_or_else(|| ConfigError::Unknown { name: name.trim().to_string() })?;
        Ok(SetArg { param, values })
    }
}

impl fmt::Display for SetArg {
    /// `NAME=VALUE[,VALUE…]`, each value as it was written.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let texts: Vec<&str> = self.values.iter().map(|o| o.text.as_str()).collect();
        write!(f, "{}={}", self.param.name, texts.join(","))
    }
}

/// Written as its text ([`fmt::Display`]) and read back through `FromStr`, so a stored argument
/// is checked again when it is read.
impl Serialize for SetArg {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> Deserialize<'de> for SetArg {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        String::deserialize(d)?.parse().map_err(serde::de::Error::custom)
    }
}

impl SetArg {
    /// Whether this argument sweeps its parameter (more than one value).
    pub fn is_sweep(&self) -> bool {
        self.values.len() > 1
    }
}

/// A parameter swept over several values.
#[derive(Clone, Debug, PartialEq)]
pub struct Sweep {
    /// The parameter.
    pub param: &'static Param,
    /// Its values, each already checked.
    pub values: Vec<Override>,
}

/// The `--set` arguments of one run together: parameters with one value, and at most one swept.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SetArgs {
    /// Parameters with one value, in the order given.
    pub fixed: Vec<Override>,
    /// The swept parameter and its values.
    pub sweep: Option<Sweep>,
}

impl SetArgs {
    /// Puts the arguments together, refusing a second swept parameter and values that together
    /// put `min_scale` above `max_scale` (the fixed ones, with each swept value).
    pub fn new(args: &[SetArg]) -> Result<SetArgs, ConfigError> {
        let mut all = SetArgs::default();
        for a in args {
            if !a.is_sweep() {
                all.fixed.extend(a.values.iter().cloned());
            } else if all.sweep.is_some() {
                return Err(ConfigError::TwoSweeps(a.to_string()));
            } else {
                all.sweep = Some(Sweep { param: a.param, values: a.values.clone() });
            }
        }
        match &all.sweep {
            None => Config::default().apply(&all.fixed)?,
            Some(s) => {
                for v in &s.values {
                    Config::default().apply(&[all.fixed.as_slice(), std::slice::from_ref(v)].concat())?;
                }
            }
        }
        Ok(all)
    }

    /// Single values only, for a run that sweeps nothing: refuses a list of values, then puts
    /// the values together as [`SetArgs::new`] does.
    pub fn single_values(args: &[SetArg]) -> Result<Vec<Override>, ConfigError> {
        if let Some(a) = args.iter().find(|a| a.is_sweep()) {
            return Err(ConfigError::NoSweepHere(a.to_string()));
        }
        Ok(SetArgs::new(args)?.fixed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arg(s: &str) -> Result<SetArg, ConfigError> {
        s.parse()
    }

    #[test]
    fn a_value_is_read_once_and_checked_against_its_range() {
        let a = arg(" snap_threshold = 0.2 ").unwrap();
        assert_eq!(a.param.name, "snap_threshold");
        let o = &a.values[0];
        assert_eq!((o.name, o.value, o.text.as_str()), ("snap_threshold", 0.2, "0.2"));
        assert!(!a.is_sweep());
        assert!(matches!(arg("snap_threshold"), Err(ConfigError::NotNameValue(_))));
        assert!(matches!(arg("snap=1"), Err(ConfigError::Unknown { .. })));
        assert!(matches!(arg("snap_threshold=x"), Err(ConfigError::NotANumber { .. })));
        assert!(matches!(arg("snap_threshold="), Err(ConfigError::NotANumber { .. })));
        assert_eq!(
            arg("snap_threshold=0.1,12").unwrap_err().to_string(),
            "snap_threshold: '12' must be a number from 0 to 10 m"
        );
    }

    #[test]
    fn a_list_is_a_sweep_of_checked_values() {
        let a = arg("snap_threshold=0.05, 0.1,0.30").unwrap();
        assert!(a.is_sweep());
        assert_eq!(a.values.iter().map(|o| o.value).collect::<Vec<_>>(), [0.05, 0.1, 0.3]);
        // Written back as given, without the spaces around the values.
        assert_eq!(a.to_string(), "snap_threshold=0.05,0.1,0.30");
        assert_eq!(arg(&a.to_string()).unwrap(), a);
        assert_eq!(
            arg("snap_threshold=0.1,").unwrap_err().to_string(),
            "snap_threshold=0.1,: an empty value in the list"
        );
        assert!(matches!(arg("snap_threshold=,0.1"), Err(ConfigError::EmptyValue(_))));
    }

    #[test]
    fn a_stored_argument_is_checked_again_when_read() {
        let a = arg("touchpad_move_rate=3").unwrap();
        let json = serde_json::to_string(&a).unwrap();
        assert_eq!(json, r#""touchpad_move_rate=3""#);
        assert_eq!(serde_json::from_str::<SetArg>(&json).unwrap(), a);
        let bad = serde_json::from_str::<SetArg>(r#""touchpad_move_rate=1000""#).unwrap_err().to_string();
        assert!(bad.contains("touchpad_move_rate: '1000' must be a number from 0 to 100 m/s"), "{bad}");
    }

    #[test]
    fn a_run_has_at_most_one_sweep_and_values_that_hold_together() {
        let args: Vec<SetArg> =
            ["spawn_distance=2", "snap_threshold=0.1,0.2", "spawn_drop=0.3"].iter().map(|s| arg(s).unwrap()).collect();
        let set = SetArgs::new(&args).unwrap();
        assert_eq!(set.fixed.iter().map(|o| o.name).collect::<Vec<_>>(), ["spawn_distance", "spawn_drop"]);
        let sweep = set.sweep.unwrap();
        assert_eq!((sweep.param.name, sweep.values.len()), ("snap_threshold", 2));
        let two = [arg("snap_threshold=0.1,0.2").unwrap(), arg("spawn_distance=1,2").unwrap()];
        assert_eq!(
            SetArgs::new(&two).unwrap_err().to_string(),
            "spawn_distance=1,2: only one parameter can be swept at a time"
        );
        let order = [arg("min_scale=5").unwrap(), arg("max_scale=2").unwrap()];
        assert!(matches!(SetArgs::new(&order), Err(ConfigError::ScaleOrder { .. })));
        assert!(matches!(SetArgs::single_values(&order), Err(ConfigError::ScaleOrder { .. })));
        // A swept value is checked with the fixed ones.
        let swept = [arg("max_scale=2").unwrap(), arg("min_scale=1,3").unwrap()];
        assert!(matches!(SetArgs::new(&swept), Err(ConfigError::ScaleOrder { min, .. }) if min == 3.0));
        // Where nothing is swept, a list is refused.
        let e = SetArgs::single_values(&[arg("snap_threshold=0.1,0.2").unwrap()]).unwrap_err();
        assert!(matches!(e, ConfigError::NoSweepHere(_)), "{e}");
        assert_eq!(SetArgs::single_values(&args[..1]).unwrap()[0].value, 2.0);
    }
}
