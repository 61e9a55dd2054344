//! The command line `dirac` on an element-wise system (sizes chosen in the file's `[sizes]`): the
//! run written to Parquet through the same observer as every other run, the same states, bit for
//! bit, as the compiled-in system; a start of the wrong length refused by name.

use std::path::{Path, PathBuf};
use std::process::Command;

use dirac::prelude::*;
use dirac_io::read::{key_values, read_f64_column, row_count};

#[allow(dead_code)]
#[path = "../../examples/common/toda_n.rs"]
mod toda_n;
use toda_n::{initial, TodaN};

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

/// The periodic Toda lattice's attribute and function, as the examples compile it in.
fn toda_text() -> String {
    let src = include_str!("../../examples/common/toda_n.rs");
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

/// A TOML array of the values, each in Rust's shortest form that reads back to its bits.
fn array(values: &[f64]) -> String {
    let items: Vec<String> = values.iter().map(|v| format!("{v:?}")).collect();
    format!("[{}]", items.join(", "))
}

/// The system file of the lattice of `n` particles from `start`.
fn toda_toml(method: &str, q: &[f64], p: &[f64]) -> String {
    format!(
        "system = \"toda.rs\"\nsteps = 30\nmethod = \"{method}\"\nout = \"toda.parquet\"\n\n\
         [parameters]\nm = 1.0\nd = 1.0\nh = 0.05\n\n[sizes]\nn = 8\n\n[start]\nq = {}\np = {}\n",
        array(q),
        array(p)
    )
}

#[test]
fn an_element_wise_system_file_runs_into_parquet_as_the_compiled_in_system() {
    let dir = scratch("cli_toda");
    std::fs::write(dir.join("toda.rs"), toda_text()).unwrap();
    let sys = TodaN {
        m: 1.0,
        d: 1.0,
        h: 0.05,
        n: 8,
    };
    let start = initial(&sys, 0.1, 0.3, 0.05);
    for (method, integ) in [
        (
            "plus",
            ElementIntegrator::new(sys, NewtonOptions::default()),
        ),
        (
            "minus",
            ElementIntegrator::minus(sys, NewtonOptions::default()),
        ),
    ] {
        let toml = toda_toml(method, start.q.as_slice(), start.p.as_slice());
        std::fs::write(dir.join("toda.toml"), toml).unwrap();
        let file = dir.join("toda.toml");
        let (status, stdout, stderr) = dirac(&["run", file.to_str().unwrap()]);
        assert_eq!(status, 0, "{method}: {stderr}");
        assert!(stdout.contains("30 steps"), "{stdout}");
        let out = dir.join("toda.parquet");
        let reference = integ.run(start.clone()).steps(30).collect().unwrap();
        assert_eq!(row_count(&out).unwrap(), 31);
        for i in 0..8 {
            let q = read_f64_column(&out, &format!("q_{i}")).unwrap();
            let p = read_f64_column(&out, &format!("p_{i}")).unwrap();
            for (k, s) in reference.states.iter().enumerate() {
                assert_eq!(
                    q[k].to_bits(),
                    s.q[i].to_bits(),
                    "{method}: q_{i}, step {k}"
                );
                assert_eq!(
                    p[k].to_bits(),
                    s.p[i].to_bits(),
                    "{method}: p_{i}, step {k}"
                );
            }
        }
        let kv = key_values(&out).unwrap();
        assert_eq!(kv["dirac.sizes"], "n=8");
        assert_eq!(kv["dirac.outcome"], "completed");
    }
    let (status, stdout, _) = dirac(&["check", dir.join("toda.toml").to_str().unwrap()]);
    assert_eq!(status, 0);
    assert!(stdout.contains("sizes: n"), "{stdout}");
}

/// A start whose length is not the system's at the file's sizes: exit status 1, naming the key
/// and both lengths; nothing is integrated.
#[test]
fn an_element_wise_start_of_another_length_is_refused() {
    let dir = scratch("cli_toda_short");
    std::fs::write(dir.join("toda.rs"), toda_text()).unwrap();
    let toml = toda_toml("plus", &[0.0; 4], &[0.0; 8]);
    std::fs::write(dir.join("toda.toml"), toml).unwrap();
    let (status, _, stderr) = dirac(&["run", dir.join("toda.toml").to_str().unwrap()]);
    assert_eq!(status, 1, "{stderr}");
    assert!(
        stderr.contains("`start.q` has 4 values; the system has 8"),
        "{stderr}"
    );
    assert!(!dir.join("toda.parquet").exists());
}
