//! The built-in grammars, written in the grammar file format (`docs/lsystem.md`): Paul Bourke's
//! three bushes, the six plants of The Algorithmic Beauty of Plants Fig. 1.24 (a–f), and four 3D
//! trees shaped like the species grove ships.

use super::error::LsystemError;
use super::grammar::Grammar;

/// `(name, grammar file text)` of every preset.
pub const PRESETS: &[(&str, &str)] = &[
    (
        "bush1",
        "name: bush1\n# Paul Bourke, L-system user notes, bush 1.\nangle: 25.7\naxiom: Y\nrule: X -> X[-FFF][+FFF]FX\nrule: Y -> YFX[+Y][-Y]\nn: 6\n",
    ),
    (
        "bush2",
        "name: bush2\n# Paul Bourke, L-system user notes, bush 2.\nangle: 22.5\naxiom: F\nrule: F -> FF+[+F-F-F]-[-F+F+F]\nn: 4\n",
    ),
    (
        "bush3",
        "name: bush3\n# Paul Bourke, L-system user notes, bush 3.\nangle: 35\naxiom: F\nrule: F -> F[+FF][-FF]F[-F][+F]F\nn: 4\n",
    ),
    ("abop-a", "name: abop-a\n# ABOP Fig. 1.24a.\nangle: 25.7\naxiom: F\nrule: F -> F[+F]F[-F]F\nn: 5\n"),
    ("abop-b", "name: abop-b\n# ABOP Fig. 1.24b.\nangle: 20\naxiom: F\nrule: F -> F[+F]F[-F][F]\nn: 5\n"),
    ("abop-c", "name: abop-c\n# ABOP Fig. 1.24c.\nangle: 22.5\naxiom: F\nrule: F -> FF-[-F+F+F]+[+F-F-F]\nn: 4\n"),
    ("abop-d", "name: abop-d\n# ABOP Fig. 1.24d.\nangle: 20\naxiom: X\nrule: X -> F[+X]F[-X]+X\nrule: F -> FF\nn: 7\n"),
    (
        "abop-e",
        "name: abop-e\n# ABOP Fig. 1.24e.\nangle: 25.7\naxiom: X\nrule: X -> F[+X][-X]FX\nrule: F -> FF\nn: 7\n",
    ),
    (
        "abop-f",
        "name: abop-f\n# ABOP Fig. 1.24f.\nangle: 22.5\naxiom: X\nrule: X -> F-[[X]+X]+F[+FX]-X\nrule: F -> FF\nn: 5\n",
    ),
    (
        "broadleaf",
        "name: broadleaf\n# A round crown: three (or two) branches at every fork, after ABOP Fig. 1.25.\n\
         species: broadleaf\nangle: 22.5\nstep: 0.45\nwidth: 0.32\nwidth-factor: 0.7\n\
         axiom: FFA\n\
         rule: A -(0.7)-> [&F!A]/////[&F!A]///////[&F!A]\n\
         rule: A -(0.3)-> [&F!A]////////[&&F!A]\n\
         rule: F -> S/////F\nrule: S -> F\nheight: 8\nn: 7\n",
    ),
    (
        "conifer",
        "name: conifer\n# A cone of whorls: five thin level branches per whorl, the oldest (lowest) longest;\n\
         # every branch segment carries four twigs of needles, and the leader two between whorls.\n\
         # Branches grow every other step, the leader two segments a step.\n\
         species: conifer\nangle: 18\nstep: 0.3\nwidth: 0.2\nwidth-factor: 0.85\n\
         axiom: FFA\n\
         rule: A -> F[&&&!!!!!!C]/////[&&&!!!!!!C]F!W/A\n\
         rule: W -> [&&&&&!!!!!!B]////[&&&&&!!!!!!B]////[&&&&&!!!!!!B]////[&&&&&!!!!!!B]////[&&&&&!!!!!!B]\n\
         rule: B -> F[-C][+C][&C][^^C]E\nrule: E -> !B\nrule: C -> !F\nheight: 10\nn: 14\n",
    ),
    (
        "birch",
        "name: birch\n# A slender leader with thin branches that arc downwards.\n\
         species: birch\nangle: 20\nstep: 0.4\nwidth: 0.16\nwidth-factor: 0.6\n\
         axiom: FFFFA\n\
         rule: A -(0.5)-> FF[&&&!B]/////A\n\
         rule: A -(0.5)-> FF[&&!B]///////[&&&!B]///A\n\
         rule: B -> F[+&C][-&C]E\nrule: E -> B\nrule: C -> F&D\nrule: D -> F\nheight: 9\nn: 10\n",
    ),
    (
        "shrub",
        "name: shrub\n# Many stems from the ground; side branches and twigs turn at most twice, so nothing grows\n\
         # below the horizontal.\n\
         species: shrub\nangle: 20\nstep: 0.22\nwidth: 0.06\nwidth-factor: 0.8\n\
         axiom: [&A]////[&&A]////[&A]////[&&A]////[&A]\n\
         rule: A -(0.6)-> F[+B]//[-B]A\n\
         rule: A -(0.4)-> F//[&B]A\n\
         rule: B -> F[+C]F[-C]B\nrule: C -> F\nheight: 1.6\nn: 6\n",
    ),
];

/// The names of the presets.
pub fn names() -> Vec<&'static str> {
    PRESETS.iter().map(|p| p.0).collect()
}

/// The preset called `name`, or an error naming the known ones.
pub fn preset(name: &str) -> Result<Grammar, LsystemError> {
    match PRESETS.iter().find(|p| p.0 == name) {
        Some((n, text)) => Grammar::parse_file(text, &format!("preset {n}")),
        None => Err(LsystemError::UnknownPreset { name: name.to_string(), known: names().join(", ") }),
    }
}
