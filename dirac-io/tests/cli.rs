//! The command line `dirac`: a system file (the attribute and function as text, parameters, a
//! start) run into Parquet — the same states, bit for bit, as the compiled-in system; columns
//! named after the text's coordinates; mistakes in the file and in the text, and a failed step,
//! reported with their exit statuses.

use std::path::{Path, PathBuf};
use std::process::Command;

use dirac::prelude::*;
use dirac::systems::kepler::Kepler;
use dirac_io::read::last_state;
use dirac_io::StateColumns;

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

/// The text of Kepler's system as the facade compiles it in.
fn kepler_text() -> String {
    let src = include_str!("../../src/systems/kepler.rs");
    let start = src.find("#[reduced_lagrangian").expect("the attribute");
    let end = start + src[start..].find("\n}\n").expect("the body's end") + 2;
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

const KEPLER_TOML: &str = r#"system = "kepler.rs"
steps = 1000
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
fn a_system_file_runs_into_parquet_as_the_compiled_in_system() {
    let dir = scratch("cli_kepler");
    std::fs::write(dir.join("kepler.rs"), kepler_text()).unwrap();
    let kepler = Kepler::unit(0.01);
    let start = kepler.periapsis_state(1.0, 0.5);
    assert_eq!(start.mu[0], 0.8660254037844386);
    let columns = ReducedState::<1, 1>::column_names(&["r"], &["phi"]);
    let opts = NewtonOptions::default();
    let plus = ReducedIntegrator::plus(kepler, opts)
        .run(start)
        .steps(1000)
        .collect();
    let minus = ReducedIntegrator::minus(kepler, opts)
        .run(start)
        .steps(1000)
        .collect();
    for (method, compiled) in [("plus", plus.unwrap()), ("minus", minus.unwrap())] {
        let file = dir.join(format!("{method}.toml"));
        std::fs::write(&file, KEPLER_TOML.replace("METHOD", method)).unwrap();
        let (code, stdout, stderr) = dirac(&["run", file.to_str().unwrap()]);
        assert_eq!(code, 0, "{stderr}");
        assert!(stdout.contains("1000 steps"), "{stdout}");
        let (step, t, last) =
            last_state::<ReducedState<1, 1>>(&dir.join("kepler.parquet"), &columns).unwrap();
        assert_eq!((step, t), (1000, compiled.times[1000]));
        assert_eq!(last, compiled.states[1000], "{method}");
    }
    // The unreduced equations, from (q, p).
    let file = dir.join("unreduced.toml");
    let text = KEPLER_TOML.replace("METHOD", "unreduced").replace(
        "x = [0.5]\nw = [0.0]\nmu = [0.8660254037844386]\ng = [0.0]",
        "q = [0.5, 0.0]\np = [0.0, 0.8660254037844386]",
    );
    std::fs::write(&file, text).unwrap();
    let (code, _, stderr) = dirac(&[
        "run",
        file.to_str().unwrap(),
        "--out",
        dir.join("u.parquet").to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let columns = UnreducedState::<2>::column_names(&["r"], &["phi"]);
    let (_, _, last) = last_state::<UnreducedState<2>>(&dir.join("u.parquet"), &columns).unwrap();
    let compiled = UnreducedIntegrator::new(kepler, NewtonOptions::default())
        .run(kepler.untrivialize(&start))
        .steps(1000)
        .collect()
        .unwrap();
    assert_eq!(last, compiled.states[1000]);
}

/// Kepler's problem as a continuous Lagrangian, compiled in from the same characters the file's
/// text holds.
const KEPLER_L: &str = "#[reduced_lagrangian(shape(r), group(phi), rule = midpoint)]
fn kepler_l(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.phi * v.phi) + k / q.r
}
";

#[reduced_lagrangian(shape(r), group(phi), rule = midpoint)]
fn kepler_l(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.phi * v.phi) + k / q.r
}

#[test]
fn a_system_file_runs_at_high_order_as_the_compiled_in_system() {
    let dir = scratch("cli_gauss");
    std::fs::write(dir.join("kepler.rs"), KEPLER_L).unwrap();
    let sys = KeplerL { k: 1.0, h: 0.01 };
    let start = ReducedState::new([0.5], [0.0], [0.8660254037844386], [0.0]);
    let opts = NewtonOptions::default();
    let columns = ReducedState::<1, 1>::column_names(&["r"], &["phi"]);
    let file = dir.join("gauss.toml");
    for (method, compiled) in [
        (
            "plus",
            ReducedGaussIntegrator::plus(sys, 4, opts)
                .unwrap()
                .run(start)
                .steps(1000)
                .collect(),
        ),
        (
            "minus",
            ReducedGaussIntegrator::minus(sys, 4, opts)
                .unwrap()
                .run(start)
                .steps(1000)
                .collect(),
        ),
    ] {
        let text = KEPLER_TOML
            .replace("METHOD", method)
            .replace("out = ", "scheme = \"gauss\"\norder = 8\nout = ");
        std::fs::write(&file, text).unwrap();
        let (code, _, stderr) = dirac(&["run", file.to_str().unwrap()]);
        assert_eq!(code, 0, "{stderr}");
        let (step, _, last) =
            last_state::<ReducedState<1, 1>>(&dir.join("kepler.parquet"), &columns).unwrap();
        let compiled = compiled.unwrap();
        assert_eq!(step, 1000);
        assert_eq!(last, compiled.states[1000], "{method}");
        assert_eq!(last.mu, start.mu);
    }
    // Order 4 by the triple jump of the second-order integrator, as compiled in.
    let text = KEPLER_TOML
        .replace("METHOD", "plus")
        .replace("out = ", "order = 4\nout = ");
    std::fs::write(&file, text).unwrap();
    let (code, _, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    let (_, _, last) =
        last_state::<ReducedState<1, 1>>(&dir.join("kepler.parquet"), &columns).unwrap();
    let composed = Composition::new(
        ReducedIntegrator::plus(sys, opts),
        CompositionMethod::TRIPLE_JUMP,
    )
    .run(start)
    .steps(1000)
    .collect()
    .unwrap();
    assert_eq!(last, composed.states[1000]);
    // An odd order: the request refused, status 1, what is accepted said.
    let text = KEPLER_TOML
        .replace("METHOD", "plus")
        .replace("out = ", "scheme = \"gauss\"\norder = 7\nout = ");
    std::fs::write(&file, text).unwrap();
    let (code, _, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("even order from 2 to 32"), "{stderr}");
    // A scheme that is not a word: a malformed file, status 2.
    let text = KEPLER_TOML
        .replace("METHOD", "plus")
        .replace("out = ", "scheme = 3\nout = ");
    std::fs::write(&file, text).unwrap();
    let (code, _, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("`scheme` is"), "{stderr}");
}

#[test]
fn mistakes_and_failures_have_their_exit_statuses() {
    let dir = scratch("cli_mistakes");
    std::fs::write(dir.join("kepler.rs"), kepler_text()).unwrap();
    // A malformed file: status 2, the key named.
    let file = dir.join("bad.toml");
    std::fs::write(&file, KEPLER_TOML.replace("METHOD", "sideways")).unwrap();
    let (code, _, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("`method` is"), "{stderr}");
    // A mistake in the text: status 1, the attribute's message at its line and column.
    std::fs::write(
        dir.join("kepler.rs"),
        kepler_text().replace("q1.phi - q0.phi", "q1.psi - q0.phi"),
    )
    .unwrap();
    let file = dir.join("ok.toml");
    std::fs::write(&file, KEPLER_TOML.replace("METHOD", "plus")).unwrap();
    let (code, _, stderr) = dirac(&["check", file.to_str().unwrap()]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("unknown coordinate `psi`") && stderr.contains(" --> 4:"),
        "{stderr}"
    );
    // A system with more constraints than the fixed-size instances serve runs on its element
    // view; these four cannot all hold at the start: status 1, the step named.
    std::fs::write(
        dir.join("kepler.rs"),
        "#[reduced_lagrangian(shape(x, y), group(), rule = midpoint,\n\
         constraints = |q| [q.x, q.y, q.x + q.y, q.x - q.y])]\n\
         fn ring(q: Config, v: Velocity, m: f64) -> f64 { 0.5 * m * (v.x * v.x + v.y * v.y) }\n",
    )
    .unwrap();
    std::fs::write(
        &file,
        "system = \"kepler.rs\"\nsteps = 10\nmethod = \"unreduced\"\n[parameters]\nm = 1.0\nh = 0.1\n\
         [start]\nq = [1.0, 0.0]\np = [0.0, 1.0]\n",
    )
    .unwrap();
    let (code, _, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("constraint violated"), "{stderr}");
    // A failed step: status 1, and the states before it are on disk.
    std::fs::write(
        dir.join("wall.rs"),
        "#[reduced_lagrangian(shape(x), group())]\n\
         fn wall(q0: Config, q1: Config, h: f64, c: f64) -> f64 {\n\
         0.5 / h * (q1.x - q0.x) * (q1.x - q0.x) - h * c * q0.x.sqrt()\n}\n",
    )
    .unwrap();
    let file = dir.join("wall.toml");
    std::fs::write(
        &file,
        "system = \"wall.rs\"\nsteps = 100\n[parameters]\nh = 0.1\nc = 1e-6\n[start]\nx = [1.0]\nw = [-1.0]\n",
    )
    .unwrap();
    let (code, _, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("the states before it are written"),
        "{stderr}"
    );
    let columns = ReducedState::<1, 0>::column_names(&["x"], &[]);
    let (step, _, _) =
        last_state::<ReducedState<1, 0>>(&dir.join("wall.parquet"), &columns).unwrap();
    assert!(0 < step && step < 100, "{step}");
}

/// The heavy top of the facade, as it compiles it in, and its system file.
fn heavy_top_text() -> String {
    let src = include_str!("../../src/systems/rotations.rs");
    let at = src.find("pub fn heavy_top(").expect("the heavy top");
    let start = src[..at]
        .rfind("#[reduced_lagrangian")
        .expect("its attribute");
    let end = at + src[at..].find("\n}\n").expect("the body's end") + 2;
    src[start..end].to_owned()
}

const TOP_TOML: &str = r#"system = "top.rs"
steps = 500
method = "METHOD"
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
fn a_system_on_rotation_groups_runs_into_parquet_as_the_compiled_in_one() {
    use dirac::runtime::nalgebra::Matrix3;
    use dirac::systems::rotations::{HeavyTop, HeavyTopConfig, HeavyTopMomentum};
    let dir = scratch("cli_top");
    std::fs::write(dir.join("top.rs"), heavy_top_text()).unwrap();
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
    let (point, chart) = dirac_io::lie_names(&[("r", CoordinateKind::ROTATION)]);
    let point: Vec<&str> = point.iter().map(String::as_str).collect();
    let chart: Vec<&str> = chart.iter().map(String::as_str).collect();
    let opts = NewtonOptions::default();
    let file = dir.join("plus.toml");
    std::fs::write(&file, TOP_TOML.replace("METHOD", "plus")).unwrap();
    let (code, stdout, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("500 steps"), "{stdout}");
    let compiled = LieIntegrator::new(top, opts)
        .run(start)
        .steps(500)
        .collect()
        .unwrap();
    let columns = LieState::<9, 3>::column_names(&point, &chart);
    let (step, _, last) = last_state::<LieState<9, 3>>(&dir.join("top.parquet"), &columns).unwrap();
    assert_eq!((step, last), (500, compiled.states[500]));
    // Reduced by the rotations about the vertical: μ is in the file.
    std::fs::write(&file, TOP_TOML.replace("METHOD", "reduced")).unwrap();
    let (code, _, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    let integ = ReducedLieIntegrator::new(top, opts);
    let compiled = integ
        .run(integ.reduce(&start))
        .steps(500)
        .collect()
        .unwrap();
    let columns = ReducedLieState::<9, 3>::column_names(&point, &chart);
    let (_, _, last) =
        last_state::<ReducedLieState<9, 3>>(&dir.join("top.parquet"), &columns).unwrap();
    assert_eq!(last, compiled.states[500]);
    // `check` names the coordinates; a matrix that is not a rotation is refused.
    let (code, stdout, _) = dirac(&["check", file.to_str().unwrap()]);
    assert_eq!(code, 0);
    assert!(stdout.contains("coordinates: r (rotation)"), "{stdout}");
    let skewed = TOP_TOML
        .replace("METHOD", "plus")
        .replace("0.8, -0.6", "0.9, -0.6");
    std::fs::write(&file, skewed).unwrap();
    let (code, _, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("is not a rotation"), "{stderr}");
}

/// A pendulum whose rod is a holonomic constraint, compiled in here and given to the command
/// line as text: the constrained integrator's states are the same, bit for bit.
#[reduced_lagrangian(shape(x, y), group(), rule = midpoint,
    constraints = |q| [q.x * q.x + q.y * q.y - l * l])]
fn rod(q: Config, v: Velocity, m: f64, l: f64, g: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.y * v.y) - m * g * q.y
}

#[test]
fn a_system_with_constraints_runs_into_parquet_as_the_compiled_in_one() {
    let dir = scratch("cli_rod");
    std::fs::write(
        dir.join("rod.rs"),
        "#[reduced_lagrangian(shape(x, y), group(), rule = midpoint,\n\
             constraints = |q| [q.x * q.x + q.y * q.y - l * l])]\n\
         fn rod(q: Config, v: Velocity, m: f64, l: f64, g: f64) -> f64 {\n\
             0.5 * m * (v.x * v.x + v.y * v.y) - m * g * q.y\n\
         }\n",
    )
    .unwrap();
    let file = dir.join("rod.toml");
    std::fs::write(
        &file,
        "system = \"rod.rs\"\nsteps = 400\nmethod = \"unreduced\"\n\
         [parameters]\nm = 1.0\nl = 1.5\ng = 9.81\nh = 0.01\n\
         [start]\nq = [1.2, -0.9]\np = [0.0, 0.0]\n",
    )
    .unwrap();
    let (code, stdout, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("400 steps"), "{stdout}");
    let sys = Rod {
        m: 1.0,
        l: 1.5,
        g: 9.81,
        h: 0.01,
    };
    let compiled = ConstrainedIntegrator::new(sys, NewtonOptions::default())
        .run(UnreducedState::new([1.2, -0.9], [0.0, 0.0]))
        .steps(400)
        .collect()
        .unwrap();
    let columns = UnreducedState::<2>::column_names(&["x", "y"], &[]);
    let (step, t, last) =
        last_state::<UnreducedState<2>>(&dir.join("rod.parquet"), &columns).unwrap();
    assert_eq!((step, t), (400, compiled.times[400]));
    assert_eq!(last, compiled.states[400]);
}

/// A key of `[start]` that the system does not start from is refused as an unknown top-level
/// key is (status 2, the key and the accepted ones named), not ignored; so is a coordinate of
/// `[start.q]`/`[start.p]` that the system does not have.
#[test]
fn unknown_start_keys_are_refused_naming_them() {
    let dir = scratch("cli_start_keys");
    std::fs::write(dir.join("kepler.rs"), kepler_text()).unwrap();
    std::fs::write(dir.join("top.rs"), heavy_top_text()).unwrap();
    let file = dir.join("kepler.toml");
    let refused = |text: String, key: &str, accepted: &str| {
        std::fs::write(&file, text).unwrap();
        for command in ["run", "check"] {
            let (code, _, stderr) = dirac(&[command, file.to_str().unwrap()]);
            assert_eq!(code, 2, "{command}: {stderr}");
            assert!(
                stderr.contains(&format!("unknown key `start.{key}`; accepted: {accepted}")),
                "{command}: {stderr}"
            );
            assert!(stderr.contains("kepler.toml"), "{stderr}");
        }
    };
    // A misspelled momentum beside the right ones: it was ignored and the run completed.
    let reduced = KEPLER_TOML.replace("METHOD", "plus");
    refused(format!("{reduced}mu_0 = [1.0]\n"), "mu_0", "x, w, mu, g");
    // An unreduced run's keys in a reduced run's start, and the other way round.
    refused(format!("{reduced}q = [1.0, 0.0]\n"), "q", "x, w, mu, g");
    let unreduced = "system = \"kepler.rs\"\nsteps = 10\nmethod = \"unreduced\"\n\
                     [parameters]\nh = 0.01\nk = 1.0\n[start]\nq = [0.5, 0.0]\np = [0.0, 1.0]\n";
    refused(format!("{unreduced}w = [0.0]\n"), "w", "q, p");
    // The right keys still run.
    std::fs::write(&file, &reduced).unwrap();
    let (code, _, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    // On rotation groups: tables of the coordinates under `q`, `p` or `v` only, and only the
    // system's coordinates in them.
    let top = dir.join("top.toml");
    let text = TOP_TOML.replace("METHOD", "plus");
    std::fs::write(&top, format!("{text}\n[start.w]\nr = [0.0, 0.0, 0.0]\n")).unwrap();
    let (code, _, stderr) = dirac(&["run", top.to_str().unwrap()]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("unknown key `start.w`; accepted: q, p, v"),
        "{stderr}"
    );
    std::fs::write(&top, text.replace("[start.p]\nr =", "[start.p]\nr2 =")).unwrap();
    let (code, _, stderr) = dirac(&["run", top.to_str().unwrap()]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("`start.p.r2` is not a coordinate; the coordinates: r"),
        "{stderr}"
    );
}

/// The same items compiled in here and, as text, given to the command line.
macro_rules! compiled_and_text {
    ($text:ident: $($item:tt)*) => {
        $($item)*
        const $text: &str = stringify!($($item)*);
    };
}

compiled_and_text!(BODY_IN_SPACE:
    /// A rigid body in space as one pose (`J = diag(1, 2, 3)`, so `J_d = diag(2, 1, 0)`), in
    /// gravity, with a thrust along its third axis as the trapezoid rule's discrete forces.
    #[reduced_lagrangian(pose(b),
        force = |dq0, dq1| 0.5 * h * thrust
            * ((q0.b.rotation * Vector3::z()).dot(&dq0.b.linear)
                + (q1.b.rotation * Vector3::z()).dot(&dq1.b.linear)))]
    fn body_in_space(q0: Config, q1: Config, h: f64, m: f64, g: f64, thrust: f64) -> f64 {
        let jd = Matrix3::from_diagonal(&Vector3::new(2.0, 1.0, 0.0));
        let f = q0.b.rotation.transpose() * q1.b.rotation;
        let dx = q1.b.translation - q0.b.translation;
        ((Matrix3::identity() - f) * jd).trace() / h + 0.5 * m * dx.norm_squared() / h
            - 0.5 * h * m * g * (q0.b.translation.z + q1.b.translation.z)
    }
);

/// A pose starts from its rotation's rows and then its position, its momentum from `Π` and
/// then `p`.
const BODY_TOML: &str = r#"system = "body.rs"
steps = 500
method = "METHOD"
out = "body.parquet"

[parameters]
h = 0.01
m = 3.0
g = 9.81
thrust = 40.0

[start.q]
b = [[1.0, 0.0, 0.0], [0.0, 0.8, -0.6], [0.0, 0.6, 0.8], [1.0, -2.0, 0.5]]

[start.p]
b = [0.4, 1.0, -0.3, 0.9, -0.3, 0.6]
"#;

#[test]
fn a_body_in_space_runs_into_parquet_as_the_compiled_in_one() {
    use dirac::runtime::nalgebra::Matrix3;
    let dir = scratch("cli_body_in_space");
    std::fs::write(dir.join("body.rs"), BODY_IN_SPACE).unwrap();
    let body = BodyInSpace {
        h: 0.01,
        m: 3.0,
        g: 9.81,
        thrust: 40.0,
    };
    let start = body.state(
        &BodyInSpaceConfig {
            b: BodyInSpacePose {
                rotation: Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.8, -0.6, 0.0, 0.6, 0.8),
                translation: Vector3::new(1.0, -2.0, 0.5),
            },
        },
        &BodyInSpaceMomentum {
            b: BodyInSpacePoseMomentum {
                angular: Vector3::new(0.4, 1.0, -0.3),
                linear: Vector3::new(0.9, -0.3, 0.6),
            },
        },
    );
    let (point, chart) = dirac_io::lie_names(&[("b", CoordinateKind::POSE)]);
    let point: Vec<&str> = point.iter().map(String::as_str).collect();
    let chart: Vec<&str> = chart.iter().map(String::as_str).collect();
    let columns = LieState::<12, 6>::column_names(&point, &chart);
    let file = dir.join("body.toml");
    for (method, integ) in [
        ("plus", LieIntegrator::new(body, NewtonOptions::default())),
        (
            "minus",
            LieIntegrator::minus(body, NewtonOptions::default()),
        ),
    ] {
        std::fs::write(&file, BODY_TOML.replace("METHOD", method)).unwrap();
        let (code, stdout, stderr) = dirac(&["run", file.to_str().unwrap()]);
        assert_eq!(code, 0, "{method}: {stderr}");
        assert!(stdout.contains("500 steps"), "{stdout}");
        let compiled = integ.run(start).steps(500).collect().unwrap();
        let (step, _, last) =
            last_state::<LieState<12, 6>>(&dir.join("body.parquet"), &columns).unwrap();
        assert_eq!((step, last), (500, compiled.states[500]), "{method}");
    }
    // `check` names the coordinate and its kind; an attitude that is not a rotation is refused
    // by the coordinate's name.
    let (code, stdout, _) = dirac(&["check", file.to_str().unwrap()]);
    assert_eq!(code, 0);
    assert!(stdout.contains("coordinates: b (pose)"), "{stdout}");
    let skewed = BODY_TOML
        .replace("METHOD", "plus")
        .replace("0.8, -0.6", "0.9, -0.6");
    std::fs::write(&file, skewed).unwrap();
    let (code, _, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("`b` is not a rotation"), "{stderr}");
}

/// The method words are the one run request's (`dirac_jit::RunRequest`), read as the Python
/// package reads them: "reduced" is a system on vector spaces' "plus" and "unreduced" a
/// rotation system's, bit for bit; "reduced" of a rotation system that declares no symmetry is
/// refused before it runs (status 1), saying so.
#[test]
fn the_method_words_are_the_run_requests() {
    let dir = scratch("cli_words");
    std::fs::write(dir.join("kepler.rs"), kepler_text()).unwrap();
    std::fs::write(dir.join("body.rs"), BODY_IN_SPACE).unwrap();
    let run = |toml: &str, method: &str| {
        let system = if toml == KEPLER_TOML {
            "kepler"
        } else {
            "body"
        };
        let out = format!("{system}-{method}.parquet");
        let text = toml
            .replace("METHOD", method)
            .replace("kepler.parquet", &out)
            .replace("body.parquet", &out);
        let file = dir.join(format!("{system}-{method}.toml"));
        std::fs::write(&file, text).unwrap();
        let (code, _, stderr) = dirac(&["run", file.to_str().unwrap()]);
        (code, stderr, dir.join(out))
    };
    let kepler = ReducedState::<1, 1>::column_names(&["r"], &["phi"]);
    let states: Vec<_> = ["plus", "reduced"]
        .into_iter()
        .map(|method| {
            let (code, stderr, out) = run(KEPLER_TOML, method);
            assert_eq!(code, 0, "{method}: {stderr}");
            last_state::<ReducedState<1, 1>>(&out, &kepler).unwrap()
        })
        .collect();
    assert_eq!(states[0], states[1]);
    let (point, chart) = dirac_io::lie_names(&[("b", CoordinateKind::POSE)]);
    let point: Vec<&str> = point.iter().map(String::as_str).collect();
    let chart: Vec<&str> = chart.iter().map(String::as_str).collect();
    let body = LieState::<12, 6>::column_names(&point, &chart);
    let states: Vec<_> = ["plus", "unreduced"]
        .into_iter()
        .map(|method| {
            let (code, stderr, out) = run(BODY_TOML, method);
            assert_eq!(code, 0, "{method}: {stderr}");
            last_state::<LieState<12, 6>>(&out, &body).unwrap()
        })
        .collect();
    assert_eq!(states[0], states[1]);
    let (code, stderr, out) = run(BODY_TOML, "reduced");
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("declares no symmetry"), "{stderr}");
    assert!(!out.exists(), "nothing is written before the run");
}

/// The eight bodies on a chain of springs, compiled in from the text the dirac-jit tests and the
/// Python package read (`dirac-jit/tests/texts/eight_bodies.rs`).
#[path = "../../dirac-jit/tests/texts/eight_bodies.rs"]
mod eight_bodies;

/// Eight rigid bodies (8 rotations, 24 chart coordinates: beyond the fixed-size instances, so
/// the command line runs them at the sizes the text declares) from a system file: the file's
/// columns are named after the coordinates, and its states are the compiled-in system's, bit
/// for bit (both factor on the compiler's sparsity pattern, and the kernels perform the emitted
/// Rust's operations in its order).
#[test]
fn eight_bodies_run_from_a_system_file_as_the_compiled_in_system() {
    use dirac::runtime::lie::cayley;
    use dirac::runtime::nalgebra::Vector3;
    use eight_bodies::{EightBodies, EightBodiesConfig, EightBodiesMomentum};

    let dir = scratch("cli_eight_bodies");
    let src = include_str!("../../dirac-jit/tests/texts/eight_bodies.rs");
    let text = &src[src.find("#[reduced_lagrangian").expect("the attribute")..];
    std::fs::write(dir.join("bodies.rs"), text).unwrap();
    let rotations: Vec<_> = (1..=8)
        .map(|i| cayley(&Vector3::new(0.1 * f64::from(i), -0.2, 0.05 * f64::from(i))))
        .collect();
    let momenta: Vec<_> = (1..=8)
        .map(|i| Vector3::new(0.3, 1.0 - 0.1 * f64::from(i), -0.2 * f64::from(i)))
        .collect();
    let mut toml = String::from(
        "system = \"bodies.rs\"\nsteps = 250\nmethod = \"plus\"\nout = \"bodies.parquet\"\n\n\
         [parameters]\nh = 0.01\nk = 3.0\n\n[start.q]\n",
    );
    for (i, r) in rotations.iter().enumerate() {
        let rows: Vec<String> = (0..3)
            .map(|a| format!("[{:?}, {:?}, {:?}]", r[(a, 0)], r[(a, 1)], r[(a, 2)]))
            .collect();
        toml += &format!("r{} = [{}]\n", i + 1, rows.join(", "));
    }
    toml += "\n[start.p]\n";
    for (i, m) in momenta.iter().enumerate() {
        toml += &format!("r{} = [{:?}, {:?}, {:?}]\n", i + 1, m.x, m.y, m.z);
    }
    let file = dir.join("bodies.toml");
    std::fs::write(&file, toml).unwrap();
    let (code, stdout, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("250 steps"), "{stdout}");

    let sys = EightBodies { h: 0.01, k: 3.0 };
    let r = &rotations;
    let m = &momenta;
    let start = sys.state(
        &EightBodiesConfig {
            r1: r[0],
            r2: r[1],
            r3: r[2],
            r4: r[3],
            r5: r[4],
            r6: r[5],
            r7: r[6],
            r8: r[7],
        },
        &EightBodiesMomentum {
            r1: m[0],
            r2: m[1],
            r3: m[2],
            r4: m[3],
            r5: m[4],
            r6: m[5],
            r7: m[6],
            r8: m[7],
        },
    );
    let compiled = LieIntegrator::new(sys, NewtonOptions::default())
        .run(start)
        .steps(250)
        .collect()
        .unwrap();
    let kinds: Vec<(String, CoordinateKind)> = (1..=8)
        .map(|i| (format!("r{i}"), CoordinateKind::ROTATION))
        .collect();
    let kinds: Vec<(&str, CoordinateKind)> = kinds.iter().map(|(n, k)| (n.as_str(), *k)).collect();
    let (point, chart) = dirac_io::lie_names(&kinds);
    let point: Vec<&str> = point.iter().map(String::as_str).collect();
    let chart: Vec<&str> = chart.iter().map(String::as_str).collect();
    let columns = LieState::<72, 24>::column_names(&point, &chart);
    assert!(columns.contains(&"q_r8_22".to_owned()) && columns.contains(&"p_r8_z".to_owned()));
    let (step, _, last) =
        last_state::<LieState<72, 24>>(&dir.join("bodies.parquet"), &columns).unwrap();
    assert_eq!((step, last), (250, compiled.states[250]));
}

/// A robot from its URDF file: `urdf = "arm.urdf"` in place of `system`, the model's text
/// compiled — the states, bit for bit, of the same text compiled in the test, its columns named
/// after the joints; `check` names them; a malformed file, a missing one, and `torques` without
/// `urdf` are refused (status 2) naming what is wrong.
#[test]
fn a_robot_runs_from_its_urdf_file_as_its_model_text() {
    use dirac_multibody::{Model, TextOptions};
    let dir = scratch("cli_urdf");
    let source = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/data/three_link_arm.urdf"
    );
    std::fs::copy(source, dir.join("arm.urdf")).unwrap();
    let file = dir.join("arm.toml");
    let toml = "urdf = \"arm.urdf\"\nsteps = 300\nmethod = \"unreduced\"\n\
                [parameters]\nh = 0.01\n\
                [start]\nq = [1.2, 0.3, -0.2]\np = [0.1, -0.05, 0.02]\n";
    std::fs::write(&file, toml).unwrap();
    let (code, stdout, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("300 steps"), "{stdout}");
    let model = Model::from_urdf_file(dir.join("arm.urdf")).unwrap();
    let options = TextOptions {
        name: "arm".into(),
        torques: false,
    };
    let compiled = dirac_jit::compile_model(&model, &options).unwrap();
    let dirac_jit::Compiled::Flat(code) = &compiled.compiled else {
        panic!("a fixed base is a system on vector spaces")
    };
    let sys = code.instantiate::<3, 0, 3>(&[0.01]).unwrap();
    let traj = UnreducedIntegrator::new(sys, NewtonOptions::default())
        .run(UnreducedState::new([1.2, 0.3, -0.2], [0.1, -0.05, 0.02]))
        .steps(300)
        .collect()
        .unwrap();
    let joints: Vec<&str> = compiled
        .text
        .coordinates
        .iter()
        .map(|c| c.identifier.as_str())
        .collect();
    assert_eq!(joints, ["joint1", "joint2", "joint3"]);
    let columns = UnreducedState::<3>::column_names(&joints, &[]);
    let (step, _, last) =
        last_state::<UnreducedState<3>>(&dir.join("arm.parquet"), &columns).unwrap();
    assert_eq!((step, last), (300, traj.states[300]));
    let (code, stdout, _) = dirac(&["check", file.to_str().unwrap()]);
    assert_eq!(code, 0);
    assert!(stdout.contains("joint1"), "{stdout}");
    // Mistakes: a body with a negative mass, a missing file, torques without a robot.
    let bad = std::fs::read_to_string(dir.join("arm.urdf"))
        .unwrap()
        .replacen("<mass value=\"", "<mass value=\"-", 1);
    std::fs::write(dir.join("bad.urdf"), bad).unwrap();
    for (text, says) in [
        (toml.replace("arm.urdf", "bad.urdf"), "mass"),
        (toml.replace("arm.urdf", "missing.urdf"), "missing.urdf"),
        (
            format!(
                "torques = true\n{}",
                toml.replace("urdf = \"arm.urdf\"", "text = \"\"")
            ),
            "`torques` goes with",
        ),
    ] {
        std::fs::write(&file, text).unwrap();
        let (code, _, stderr) = dirac(&["run", file.to_str().unwrap()]);
        assert_eq!(code, 2, "{stderr}");
        assert!(stderr.contains(says), "{says}: {stderr}");
    }
}
