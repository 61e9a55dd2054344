//! `schedule = [h0, h1, ..]` in a system file: `dirac run` steps through the given sizes (the run
//! API's `StepSizes`), the same states and times, bit for bit, as the compiled-in system run on
//! the same schedule; `steps` defaults to the schedule's length; a schedule that is not positive
//! finite sizes, one for each step, is refused with what is accepted.

use std::path::{Path, PathBuf};
use std::process::Command;

use dirac::prelude::*;
use dirac::runtime::StepSizes;
use dirac::systems::kepler::Kepler;
use dirac_io::read::last_state;
use dirac_io::StateColumns;

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

/// The text of the function `name` in `src` (its attribute to its body's end).
fn function(src: &str, name: &str) -> String {
    let at = src.find(&format!("fn {name}(")).expect("the function");
    let start = src[..at]
        .rfind("#[reduced_lagrangian")
        .expect("its attribute");
    let end = at + src[at..].find("\n}\n").expect("the body's end") + 2;
    src[start..end].to_owned()
}

fn dirac(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_dirac"))
        .args(args)
        .output()
        .expect("the binary runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `n` sizes around `h`, no two neighbours equal.
fn sizes(h: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| h * (1.0 + 0.5 * (1.7 * k as f64).sin()))
        .collect()
}

fn toml_array(sizes: &[f64]) -> String {
    let items: Vec<String> = sizes.iter().map(|h| format!("{h:?}")).collect();
    format!("[{}]", items.join(", "))
}

const KEPLER_TOML: &str = r#"system = "kepler.rs"
SPAN
method = "METHOD"
out = "kepler.parquet"

[parameters]
h = 0.01
k = 1.0

[start]
x = [0.5]
w = [0.0]
mu = [0.8660254037844386]
g = [0.0]
"#;

#[test]
fn a_schedule_runs_as_the_compiled_in_system_on_the_same_schedule() {
    let dir = scratch("cli_schedule_kepler");
    let src = include_str!("../../src/systems/kepler.rs");
    std::fs::write(dir.join("kepler.rs"), function(src, "kepler")).unwrap();
    let kepler = Kepler::unit(0.01);
    let start = kepler.periapsis_state(1.0, 0.5);
    let hs = sizes(0.01, 400);
    let columns = ReducedState::<1, 1>::column_names(&["r"], &["phi"]);
    let opts = NewtonOptions::default();
    let plus = ReducedIntegrator::plus(kepler, opts);
    let minus = ReducedIntegrator::minus(kepler, opts);
    let runs = [
        (
            "plus",
            300,
            plus.run(start)
                .steps(300)
                .step_size(StepSizes(&hs))
                .collect(),
        ),
        (
            "minus",
            400,
            minus
                .run(start)
                .steps(400)
                .step_size(StepSizes(&hs))
                .collect(),
        ),
    ];
    for (method, steps, compiled) in runs {
        let compiled = compiled.unwrap();
        // 300 steps of the 400 sizes; the whole schedule when `steps` is left out.
        let span = if steps == 400 {
            format!("schedule = {}", toml_array(&hs))
        } else {
            format!("steps = {steps}\nschedule = {}", toml_array(&hs))
        };
        let file = dir.join(format!("{method}.toml"));
        let text = KEPLER_TOML.replace("SPAN", &span).replace("METHOD", method);
        std::fs::write(&file, text).unwrap();
        let (code, stdout, stderr) = dirac(&["run", file.to_str().unwrap()]);
        assert_eq!(code, 0, "{stderr}");
        assert!(stdout.contains(&format!("{steps} steps")), "{stdout}");
        let (step, t, last) =
            last_state::<ReducedState<1, 1>>(&dir.join("kepler.parquet"), &columns).unwrap();
        assert_eq!((step, t), (steps, compiled.times[steps]), "{method}");
        assert_eq!(last, compiled.states[steps], "{method}");
        // Not the fixed-step run.
        let fixed = ReducedIntegrator::plus(kepler, opts)
            .run(start)
            .steps(steps)
            .collect()
            .unwrap();
        assert_ne!(last, fixed.states[steps]);
    }
}

const TOP_TOML: &str = r#"system = "top.rs"
schedule = SCHEDULE
method = "reduced"
out = "top.parquet"

[parameters]
h = 0.01
j1 = 1.0
j2 = 1.0
j3 = 0.5
mgl = 2.0

[start.q]
r = [[1.0, 0.0, 0.0], [0.0, 0.8, -0.6], [0.0, 0.6, 0.8]]

[start.p]
r = [0.2, -0.1, 3.0]
"#;

#[test]
fn a_system_on_rotation_groups_runs_its_schedule_as_the_compiled_in_one() {
    use dirac::runtime::nalgebra::Matrix3;
    use dirac::systems::rotations::{HeavyTop, HeavyTopConfig, HeavyTopMomentum};
    let dir = scratch("cli_schedule_top");
    let src = include_str!("../../src/systems/rotations.rs");
    std::fs::write(dir.join("top.rs"), function(src, "heavy_top")).unwrap();
    let top = HeavyTop {
        h: 0.01,
        j1: 1.0,
        j2: 1.0,
        j3: 0.5,
        mgl: 2.0,
    };
    let start = top.state(
        &HeavyTopConfig {
            r: Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.8, -0.6, 0.0, 0.6, 0.8),
        },
        &HeavyTopMomentum {
            r: Vector3::new(0.2, -0.1, 3.0),
        },
    );
    let hs = sizes(0.01, 200);
    let file = dir.join("top.toml");
    std::fs::write(&file, TOP_TOML.replace("SCHEDULE", &toml_array(&hs))).unwrap();
    let (code, _, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    let integ = ReducedLieIntegrator::new(top, NewtonOptions::default());
    let compiled = integ
        .run(integ.reduce(&start))
        .steps(200)
        .step_size(StepSizes(&hs))
        .collect()
        .unwrap();
    let (point, chart) = dirac_io::lie_names(&[("r", CoordinateKind::ROTATION)]);
    let point: Vec<&str> = point.iter().map(String::as_str).collect();
    let chart: Vec<&str> = chart.iter().map(String::as_str).collect();
    let columns = ReducedLieState::<9, 3>::column_names(&point, &chart);
    let (step, t, last) =
        last_state::<ReducedLieState<9, 3>>(&dir.join("top.parquet"), &columns).unwrap();
    assert_eq!((step, t), (200, compiled.times[200]));
    assert_eq!(last, compiled.states[200]);
}

#[test]
fn a_schedule_that_is_not_one_positive_size_per_step_is_refused() {
    let dir = scratch("cli_schedule_refused");
    let src = include_str!("../../src/systems/kepler.rs");
    std::fs::write(dir.join("kepler.rs"), function(src, "kepler")).unwrap();
    let file = dir.join("bad.toml");
    for (span, status, says) in [
        ("schedule = [0.01, 0.0]", 1, "schedule[1] = 0"),
        ("schedule = [0.01, -0.01, 0.01]", 1, "schedule[1] = -0.01"),
        (
            "steps = 3\nschedule = [0.01, 0.01]",
            1,
            "2 step sizes for 3 steps",
        ),
        ("schedule = []", 2, "`steps` must be a positive integer"),
        ("schedule = 0.01", 2, "`schedule` must be an array"),
        (
            "schedule = [[0.01], [0.01]]",
            2,
            "`schedule` must be an array",
        ),
        ("schedule = [\"0.01\"]", 2, "`schedule` must be an array"),
    ] {
        let text = KEPLER_TOML.replace("SPAN", span).replace("METHOD", "plus");
        std::fs::write(&file, text).unwrap();
        let (code, _, stderr) = dirac(&["run", file.to_str().unwrap()]);
        assert_eq!(code, status, "{span}: {stderr}");
        assert!(stderr.contains(says), "{span}: {stderr}");
    }
    assert!(!dir.join("kepler.parquet").exists());
}
