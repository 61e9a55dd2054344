//! `dirac run` of systems on vector spaces beyond the fixed-size instances: the 30-coordinate
//! cart (a reduced start) and the 20-link chain with 20 constraints, the texts of
//! `dirac-jit/tests/sizes` (which compares them with the same texts compiled in), written with
//! one column per coordinate by its name, every state the library's run of the same element
//! view, bit for bit.

use std::path::{Path, PathBuf};
use std::process::Command;

use dirac::runtime::element::{ElementConstrainedIntegrator, ElementIntegrator, ElementState};
use dirac::runtime::{Drive, NewtonOptions};
use dirac_io::read::{last_state, read_f64_column};

const CART: &str = include_str!("../../dirac-jit/tests/sizes/cart30.rs");
const CHAIN: &str = include_str!("../../dirac-jit/tests/sizes/chain20.rs");

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
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

/// A TOML array of `v`.
fn array(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|x| format!("{x:?}")).collect();
    format!("[{}]", items.join(", "))
}

/// `q_<name>` and `p_<name>` of every coordinate, as the file names them.
fn columns(names: &[String]) -> Vec<String> {
    let q = names.iter().map(|n| format!("q_{n}"));
    q.chain(names.iter().map(|n| format!("p_{n}"))).collect()
}

#[test]
fn a_30_coordinate_system_file_runs_as_the_library_runs_it() {
    let dir = scratch("cli_cart30");
    std::fs::write(dir.join("cart.rs"), CART).unwrap();
    let x: Vec<f64> = (0..29).map(|i| 0.4 * (i as f64 * 0.7).sin()).collect();
    let w: Vec<f64> = (0..29).map(|i| 0.3 * (i as f64 * 1.3).cos()).collect();
    let file = dir.join("cart.toml");
    std::fs::write(
        &file,
        format!(
            "system = \"cart.rs\"\nsteps = 50\nmethod = \"plus\"\nout = \"cart.parquet\"\n\
             [parameters]\nmc = 2.0\nm = 0.5\nk = 3.0\nkappa = 1.5\nh = 0.01\n\
             [start]\nx = {}\nw = {}\nmu = [0.8]\ng = [0.1]\n",
            array(&x),
            array(&w)
        ),
    )
    .unwrap();
    let (code, stdout, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("50 steps"), "{stdout}");
    // The library's run of the same view: q = (x, g), p = (w, μ) (no connection).
    let view = dirac_jit::compile_flat_elements(CART).unwrap();
    let sys = view
        .instantiate_named(
            &[
                ("mc", 2.0),
                ("m", 0.5),
                ("k", 3.0),
                ("kappa", 1.5),
                ("h", 0.01),
            ],
            &[],
        )
        .unwrap();
    let names: Vec<String> = view
        .system()
        .coordinates
        .iter()
        .map(|c| c.name.clone())
        .collect();
    assert_eq!(names.len(), 30);
    let q: Vec<f64> = x.iter().copied().chain([0.1]).collect();
    let p: Vec<f64> = w.iter().copied().chain([0.8]).collect();
    let library = ElementIntegrator::new(sys, NewtonOptions::default())
        .run(ElementState::new(q, p))
        .steps(50)
        .collect()
        .unwrap();
    let out = dir.join("cart.parquet");
    let (step, t, last) = last_state::<ElementState>(&out, &columns(&names)).unwrap();
    assert_eq!((step, t), (50, library.times[50]));
    assert_eq!(last, library.states[50]);
    // Every state of a coordinate's column, by its name; the cart's momentum exactly kept.
    let c: Vec<f64> = library.states.iter().map(|s| s.q[29]).collect();
    assert_eq!(read_f64_column(&out, "q_c").unwrap(), c);
    let x0: Vec<f64> = library.states.iter().map(|s| s.q[0]).collect();
    assert_eq!(read_f64_column(&out, "q_x[0]").unwrap(), x0);
    assert!(read_f64_column(&out, "p_c")
        .unwrap()
        .iter()
        .all(|&mu| mu == 0.8));
}

#[test]
fn a_system_file_with_20_constraints_runs_as_the_library_runs_it() {
    let dir = scratch("cli_chain20");
    std::fs::write(dir.join("chain.rs"), CHAIN).unwrap();
    let (mut q, mut y) = (Vec::new(), Vec::new());
    let (mut px, mut py) = (0.0, 0.0);
    for i in 0..20 {
        let theta = 0.6 + 0.05 * i as f64;
        px += 0.5 * f64::sin(theta);
        py -= 0.5 * f64::cos(theta);
        q.push(px);
        y.push(py);
    }
    q.extend(y);
    let file = dir.join("chain.toml");
    std::fs::write(
        &file,
        format!(
            "system = \"chain.rs\"\nsteps = 40\nmethod = \"unreduced\"\nout = \"chain.parquet\"\n\
             [parameters]\nm = 0.7\nl = 0.5\ngr = 9.81\nh = 0.005\n\
             [start]\nq = {}\np = {}\n",
            array(&q),
            array(&[0.0; 40])
        ),
    )
    .unwrap();
    let (code, stdout, stderr) = dirac(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("40 steps"), "{stdout}");
    let view = dirac_jit::compile_flat_elements(CHAIN).unwrap();
    let sys = view
        .instantiate_named(&[("m", 0.7), ("l", 0.5), ("gr", 9.81), ("h", 0.005)], &[])
        .unwrap();
    let names: Vec<String> = view
        .system()
        .coordinates
        .iter()
        .map(|c| c.name.clone())
        .collect();
    let library = ElementConstrainedIntegrator::new(sys, NewtonOptions::default())
        .run(ElementState::new(q, vec![0.0; 40]))
        .steps(40)
        .collect()
        .unwrap();
    let out = dir.join("chain.parquet");
    let (step, _, last) = last_state::<ElementState>(&out, &columns(&names)).unwrap();
    assert_eq!(step, 40);
    assert_eq!(last, library.states[40]);
    let y19: Vec<f64> = library.states.iter().map(|s| s.q[39]).collect();
    assert_eq!(read_f64_column(&out, "q_y[19]").unwrap(), y19);
}
