//! `grove sun`: output for good arguments, one-line errors and exit code 2 for bad ones.

use std::process::{Command, Output};

fn grove(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_grove")).arg("sun").args(args).output().expect("run grove")
}

#[test]
fn json_output_has_the_angles_and_a_matching_direction() {
    let out = grove(&["--lat", "39.742476", "--lon", "-105.1786", "--utc", "2003-10-17T19:30:30Z", "--json"]);
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("stdout is JSON");
    let el = v["elevation_deg"].as_f64().unwrap();
    let az = v["azimuth_deg"].as_f64().unwrap();
    let zen = v["zenith_deg"].as_f64().unwrap();
    let d: Vec<f64> = v["direction"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    // The NREL SPA test case without refraction at sea level (see systems/tests/sun_accuracy.rs).
    assert!((zen - 50.128).abs() < 0.002, "zenith {zen}");
    assert!((az - 194.340).abs() < 0.002, "azimuth {az}");
    assert!((el + zen - 90.0).abs() < 1e-9);
    assert_eq!(d.len(), 3);
    assert!((d[1] - el.to_radians().sin()).abs() < 1e-9);
    // Azimuth 194° is just west of south: +Z (south) and a little −X (west).
    assert!(d[2] > 0.9 * el.to_radians().cos() && d[0] < 0.0);
    let same = grove_systems::systems::sun::sun_position(39.742476, -105.1786, 1_066_419_030_000).unwrap();
    assert_eq!(el, same.elevation_deg);
}

#[test]
fn text_output_names_every_quantity() {
    let out = grove(&["--lat", "-33.87", "--lon", "151.21", "--utc", "2026-06-21T02:00:00Z"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    for key in ["elevation_deg", "azimuth_deg", "zenith_deg", "direction"] {
        assert!(text.contains(key), "missing {key} in {text}");
    }
}

#[test]
fn bad_arguments_give_one_line_errors_and_exit_code_2() {
    let cases: &[(&[&str], &str)] = &[
        (&["--lat", "91", "--lon", "0", "--utc", "2026-06-21T12:00:00Z"], "latitude"),
        (&["--lat", "-90.5", "--lon", "0", "--utc", "2026-06-21T12:00:00Z"], "latitude"),
        (&["--lat", "45", "--lon", "200", "--utc", "2026-06-21T12:00:00Z"], "longitude"),
        (&["--lat", "NaN", "--lon", "0", "--utc", "2026-06-21T12:00:00Z"], "--lat"),
        (&["--lat", "45", "--lon", "inf", "--utc", "2026-06-21T12:00:00Z"], "--lon"),
        (&["--lat", "abc", "--lon", "0", "--utc", "2026-06-21T12:00:00Z"], "not a number"),
        (&["--lat", "45", "--lon", "0", "--utc", "2026-13-45T12:00:00Z"], "--utc"),
        (&["--lat", "45", "--lon", "0", "--utc", "yesterday"], "--utc"),
        (&["--lat", "45", "--lon", "0", "--utc", "2026-06-21"], "--utc"),
    ];
    for (args, needle) in cases {
        let out = grove(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: stderr {err}");
        assert!(out.stdout.is_empty(), "{args:?} printed to stdout");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: not one line: {err}");
        assert!(err.starts_with("error: "), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err} lacks {needle}");
        assert!(!err.contains("panicked") && !err.contains("internal error"), "{args:?}: {err}");
    }
}
