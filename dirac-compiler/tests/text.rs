//! The run-time front end against the attribute: every compile-fail case of the attribute
//! (`tests/ui/*/*.rs` of the workspace, with rustc's output in `.stderr`), given as text, gets the
//! same messages at the same lines and columns; and the systems it accepts have the names and
//! programs the attribute's systems have.

use std::collections::HashSet;
use std::fs;
use std::path::{Path, PathBuf};

use dirac_compiler::program::Leaf;
use dirac_compiler::text::{compile, compile_any, Diagnostic};

/// Every `(first line of the message, line, column)` of rustc's errors in a `.stderr`.
fn expected(stderr: &str, file: &str) -> HashSet<(String, usize, usize)> {
    let lines: Vec<&str> = stderr.lines().collect();
    let mut out = HashSet::new();
    for (i, line) in lines.iter().enumerate() {
        let Some(message) = line.strip_prefix("error: ") else {
            continue;
        };
        // The location follows the message's lines.
        let Some(at) = lines[i + 1..]
            .iter()
            .take_while(|l| !l.starts_with("error"))
            .find_map(|l| l.trim_start().strip_prefix("--> "))
        else {
            continue;
        };
        let Some(rest) = at.strip_prefix(file) else {
            continue;
        };
        let mut parts = rest.trim_start_matches(':').split(':');
        let (Some(l), Some(c)) = (parts.next(), parts.next()) else {
            continue;
        };
        out.insert((message.to_owned(), l.parse().unwrap(), c.parse().unwrap()));
    }
    out
}

/// The text once per function carrying the attribute, every other such function replaced by
/// spaces (newlines kept).
fn one_system_each(source: &str) -> Vec<String> {
    let file = syn::parse_file(source).expect("a UI case parses");
    let ranges: Vec<std::ops::Range<usize>> = file
        .items
        .iter()
        .filter_map(|item| match item {
            syn::Item::Fn(f)
                if f.attrs
                    .iter()
                    .any(|a| a.path().is_ident("reduced_lagrangian")) =>
            {
                Some(syn::spanned::Spanned::span(f).byte_range())
            }
            _ => None,
        })
        .collect();
    if ranges.len() <= 1 {
        return vec![source.to_owned()];
    }
    (0..ranges.len())
        .map(|keep| {
            let mut text: Vec<u8> = source.as_bytes().to_vec();
            for (i, r) in ranges.iter().enumerate() {
                if i != keep {
                    for b in &mut text[r.clone()] {
                        if *b != b'\n' {
                            *b = b' ';
                        }
                    }
                }
            }
            // Blanking multi-byte characters byte by byte keeps the text valid UTF-8 (all
            // spaces), but shifts no column on the kept lines.
            String::from_utf8(text).expect("spaces and the kept text")
        })
        .collect()
}

fn cases() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/ui");
    let mut cases = Vec::new();
    for dir in fs::read_dir(&root).expect("the workspace's UI cases") {
        let dir = dir.unwrap().path();
        if !dir.is_dir() || dir.ends_with("transition") {
            continue;
        }
        for f in fs::read_dir(&dir).unwrap() {
            let f = f.unwrap().path();
            if f.extension().is_some_and(|e| e == "rs") && f.with_extension("stderr").exists() {
                cases.push(f);
            }
        }
    }
    cases.sort();
    cases
}

/// Each mistake the attribute reports in a compile-fail case is reported by the run-time front
/// end with the same message at the same line and column. Cases whose mistake is in how other
/// code uses the emitted type (rustc's errors, not the attribute's), are counted apart; the
/// rest — every kind of system: on vector spaces, on rotation groups, element-wise — must match
/// exactly.
#[test]
fn misuse_gets_the_attributes_messages_at_the_same_places() {
    let (mut same, mut accepted) = (0, 0);
    let mut mismatches = Vec::new();
    for case in cases() {
        let source = fs::read_to_string(&case).unwrap();
        let stderr = fs::read_to_string(case.with_extension("stderr")).unwrap();
        let rel = format!(
            "tests/ui/{}/{}",
            case.parent()
                .unwrap()
                .file_name()
                .unwrap()
                .to_str()
                .unwrap(),
            case.file_name().unwrap().to_str().unwrap()
        );
        if !source.contains("reduced_lagrangian") {
            continue;
        }
        let want = expected(&stderr, &rel);
        // A case with several systems: each one alone, the others blanked so that lines and
        // columns stay where they are.
        for source in one_system_each(&source) {
            match compile_any(&source) {
                Ok(_) => accepted += 1,
                Err(e) => {
                    let got: Vec<&Diagnostic> = e.diagnostics.iter().collect();
                    let missing: Vec<String> = got
                        .iter()
                        .filter(|d| {
                            let first = d.message.lines().next().unwrap_or_default().to_owned();
                            !want.contains(&(first, d.line, d.column))
                        })
                        .map(|d| format!("{}:{}: {}", d.line, d.column, d.message))
                        .collect();
                    if missing.is_empty() {
                        same += 1;
                    } else {
                        mismatches.push(format!("{rel}: {missing:?}\n  expected {want:?}"));
                    }
                }
            }
        }
    }
    println!("{same} cases with the same messages, {accepted} accepted (rustc's errors)");
    assert!(mismatches.is_empty(), "{}", mismatches.join("\n"));
    assert!(same >= 130, "only {same} cases compared");
}

/// A rendered error shows the message, the position and a caret under the offending token.
#[test]
fn an_error_renders_with_its_line_and_a_caret() {
    let text = "#[reduced_lagrangian(shape(x), group(theta), shape(y))]\n\
                fn f(q0: Config, q1: Config, h: f64) -> f64 { q1.x - q0.x }";
    let e = compile(text).unwrap_err();
    assert_eq!(
        e.diagnostics,
        [Diagnostic {
            message: "duplicate `shape` argument".into(),
            line: 1,
            column: 46,
        }]
    );
    let shown = e.to_string();
    assert!(shown.contains(" --> 1:46"), "{shown}");
    assert!(
        shown.ends_with(&format!("\n  | {}^", " ".repeat(45))),
        "{shown}"
    );
}

/// No function with the attribute, two of them, and text that is not Rust.
#[test]
fn text_without_one_system_is_an_error() {
    let none = compile("fn f() {}").unwrap_err();
    assert!(none.diagnostics[0].message.contains("no function carries"));
    let two = compile(
        "#[reduced_lagrangian(shape(x), group())] fn f(q0: Config, q1: Config, h: f64) -> f64 { q1.x }\n\
         #[reduced_lagrangian(shape(x), group())] fn g(q0: Config, q1: Config, h: f64) -> f64 { q1.x }",
    )
    .unwrap_err();
    assert_eq!(two.diagnostics[0].line, 2);
    assert!(two.diagnostics[0].message.contains("a second function"));
    let broken = compile("fn f( {").unwrap_err();
    assert_eq!(broken.diagnostics.len(), 1);
}

/// The charged particle of the paper (§7.1): names, parameters, and programs that read what
/// their function's arguments are and evaluate to the paper's equations at a point.
#[test]
fn the_charged_particle_compiles_to_programs() {
    let system = compile(
        "#[reduced_lagrangian(shape(x, y, z), group(theta))]
         pub fn charged_particle(q0: Config, q1: Config, h: f64, m: f64, b0: f64) -> f64 {
             let (dx, dy, dz) = (q1.x - q0.x, q1.y - q0.y, q1.z - q0.z);
             let a_dot_dq = 0.5 * b0 * (-q0.y * dx + q0.x * dy);
             let s = a_dot_dq + (q1.theta - q0.theta);
             0.5 * m / h * (dx * dx + dy * dy + dz * dz) + 0.5 / h * s * s
         }",
    )
    .unwrap();
    assert_eq!(system.name, "ChargedParticle");
    assert_eq!(system.shape, ["x", "y", "z"]);
    assert_eq!(system.group, ["theta"]);
    assert_eq!(system.parameters, ["h", "m", "b0"]);
    assert_eq!((system.step, system.forced), (0, false));
    let params = [0.1, 2.0, 0.5];
    let (q0, q1) = ([0.3, -0.2, 0.1, 0.7], [0.35, -0.1, 0.05, 0.9]);
    let l = system.lagrangian.eval(&|leaf| match leaf {
        Leaf::Q0(i) => q0[i],
        Leaf::Q1(i) => q1[i],
        Leaf::Param(i) => params[i],
        other => panic!("L_d read {other:?}"),
    })[0];
    let (h, m, b0) = (params[0], params[1], params[2]);
    let (dx, dy, dz) = (q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2]);
    let s = 0.5 * b0 * (-q0[1] * dx + q0[0] * dy) + (q1[3] - q0[3]);
    let expected = 0.5 * m / h * (dx * dx + dy * dy + dz * dz) + 0.5 / h * s * s;
    assert_eq!(l, expected);
    // The (+) residual reads x_k, z, w_k, μ_k and parameters, and has N = 4 entries; its
    // Jacobian program has N + N² outputs.
    let stepper = &system.plus.stepper;
    assert_eq!(stepper.residual.outputs.len(), 4);
    assert_eq!(stepper.residual_jacobian.outputs.len(), 4 + 16);
    assert_eq!(stepper.momentum.outputs.len(), 3);
    for leaf in stepper.residual_momentum.leaves() {
        assert!(
            matches!(
                leaf,
                Leaf::X0(_) | Leaf::X1(_) | Leaf::U(_) | Leaf::W(_) | Leaf::Mu(_) | Leaf::Param(_)
            ),
            "{leaf:?}"
        );
    }
    assert_eq!(system.connection.outputs.len(), 3);
    assert!(system.unreduced.residual.operations() > 0);
}

/// An element-wise system: the stencils evaluate to the coordinates each element reads, and each
/// family's kernels are the derivatives of its element's discrete Lagrangian (checked against
/// central differences of the `value` program).
#[test]
fn an_element_wise_system_compiles_to_stencils_and_kernels() {
    use dirac_compiler::text::{compile_element, IndexExpr};
    let system = compile_element(
        "#[reduced_lagrangian(coordinates(x[n]), translate(x), rule = midpoint)]
         fn chain(q: Config, v: Velocity, k: f64, n: usize) -> f64 {
             let mut l = 0.0;
             for i in 0..n { l += 0.5 * v.x[i] * v.x[i]; }
             for i in 0..n - 1 { l -= 0.25 * k * (q.x[i + 1] - q.x[i]).powi(4); }
             l
         }",
    )
    .unwrap();
    assert_eq!(system.parameters, ["k", "h"]);
    assert_eq!((system.sizes.len(), system.translations.len()), (1, 1));
    let spring = &system.families[1];
    let (lo, hi) = &spring.stencil.loops[0];
    let n = 7;
    assert_eq!(
        (lo.eval(&[n], &[]), hi.eval(&[n], &[])),
        (Some(0), Some(n - 1))
    );
    let mut slots: Vec<Option<i64>> = spring
        .stencil
        .slots
        .iter()
        .map(|(c, ix)| {
            assert_eq!(*c, 0);
            ix[0].eval(&[n], &[3])
        })
        .collect();
    // In the order the body reads them.
    slots.sort();
    assert_eq!(slots, [Some(3), Some(4)]);
    assert_eq!(
        IndexExpr::Rem(Box::new(IndexExpr::Lit(-1)), Box::new(IndexExpr::Size(0))).eval(&[n], &[]),
        Some(n - 1)
    );
    // Parameters k = 1.3, h = 0.1, then the size n, then the loop index i = 3.
    let params = [1.3, 0.1, n as f64, 3.0];
    let at = |program: &dirac_compiler::program::Program, q0: [f64; 2], q1: [f64; 2]| {
        program.eval(&|leaf| match leaf {
            Leaf::Q0(a) => q0[a],
            Leaf::Q1(a) => q1[a],
            Leaf::Param(i) => params[i],
            other => panic!("an element reads no {other:?}"),
        })
    };
    let (q0, q1) = ([0.2, 0.5], [0.25, 0.4]);
    let value = |q0: [f64; 2], q1: [f64; 2]| at(&spring.value, q0, q1)[0];
    let d = at(&spring.d1_d2_d12, q0, q1);
    let eps = 1e-6;
    for a in 0..2 {
        let shift = |mut q: [f64; 2], by: f64| {
            q[a] += by;
            q
        };
        let d1 = (value(shift(q0, eps), q1) - value(shift(q0, -eps), q1)) / (2.0 * eps);
        let d2 = (value(q0, shift(q1, eps)) - value(q0, shift(q1, -eps))) / (2.0 * eps);
        assert!((d[a] - d1).abs() < 1e-8, "D1 L_d^e[{a}]: {} vs {d1}", d[a]);
        assert!(
            (d[2 + a] - d2).abs() < 1e-8,
            "D2 L_d^e[{a}]: {} vs {d2}",
            d[2 + a]
        );
        for b in 0..2 {
            let d1_at = |q1: [f64; 2]| at(&spring.d1_d2, q0, q1)[a];
            let d12 = (d1_at(shift_b(q1, b, eps)) - d1_at(shift_b(q1, b, -eps))) / (2.0 * eps);
            assert!(
                (d[4 + 2 * a + b] - d12).abs() < 1e-7,
                "D1 D2 L_d^e[{a}][{b}]"
            );
        }
    }
}

fn shift_b(mut q: [f64; 2], b: usize, by: f64) -> [f64; 2] {
    q[b] += by;
    q
}

/// A rigid body in space given as text, with one `pose(..)` coordinate: its kind is the
/// attribute key (the name the runtime resolves), its point has 12 entries and its chart 6, and
/// the retraction is `(R cay(ξ), x + v)`: the position moves by `v` in space, the rotation by
/// `cay(ξ)` in the body.
#[test]
fn a_pose_system_compiles_to_programs() {
    let system = dirac_compiler::text::compile_lie(
        "#[reduced_lagrangian(pose(body))]
         fn free(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
             let f = q0.body.rotation.transpose() * q1.body.rotation;
             let dx = q1.body.translation - q0.body.translation;
             (Matrix3::identity() - f).trace() / h + 0.5 * m * dx.norm_squared() / h
         }",
    )
    .unwrap();
    assert_eq!(system.coordinates.len(), 1);
    assert_eq!(system.coordinates[0].kind.name(), "pose");
    assert_eq!((system.point_len(), system.chart_len()), (12, 6));
    assert_eq!(system.stepper.residual.outputs.len(), 6);
    // The base point: a rotation about z by a quarter turn, at (1, 2, 3).
    let base = [0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 3.0];
    // ξ = (0, 0, 2): cay(ξ) turns by 2 atan(|ξ|/2) = π/2 about the body's z axis; v = (0.5, 0, -1).
    let z = [0.0, 0.0, 2.0, 0.5, 0.0, -1.0];
    let q = system.retract.eval(&|leaf| match leaf {
        Leaf::Base(i) => base[i],
        Leaf::Chart(j) => z[j],
        other => panic!("the retraction read {other:?}"),
    });
    // R cay(ξ) = Rz(π/2) Rz(π/2) = Rz(π).
    let want = [-1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0, 1.5, 2.0, 2.0];
    for (got, want) in q.iter().zip(want) {
        assert!((got - want).abs() < 1e-15, "{q:?}");
    }
}

/// A difference of the step's two positions is its chart increment: with the next point
/// `x + v` (a pose's position, a scalar), the body's `q1.x − q0.x` is `(x + v) − x`, which the
/// compiler takes as `v` ([`dirac_compiler`]'s graph cancels the common term). So for bodies
/// whose `L_d` and forces read the positions only through that difference, the residual, its
/// Jacobian, the momentum update and the sensitivities read no stored position at all, and
/// give the same values at `x = 0` and at `x = 10⁸`, bit for bit; computed as written they read
/// it, and round `v` at `|x|`.
#[test]
fn a_difference_of_the_steps_positions_is_the_chart_increment() {
    let systems = [
        // A pose, discrete, pushed along its displacement.
        "#[reduced_lagrangian(pose(body), step = h,
                 force = |dq0, dq1| c * (q1.body.translation - q0.body.translation).dot(&dq0.body.linear))]
             fn free(q0: Config, q1: Config, h: f64, m: f64, c: f64) -> f64 {
                 let f = q0.body.rotation.transpose() * q1.body.rotation;
                 let dx = q1.body.translation - q0.body.translation;
                 (Matrix3::identity() - f).trace() / h + 0.5 * m * dx.norm_squared() / h
             }",
        // A pose, continuous: its velocity `(x1 − x0)/h`.
        "#[reduced_lagrangian(pose(body), rule = trapezoid)]
             fn flying(q: Config, v: Velocity, m: f64) -> f64 {
                 0.5 * v.body.angular.norm_squared() + 0.5 * m * v.body.linear.norm_squared()
             }",
        // Scalars beside a rotation, discrete and continuous.
        "#[reduced_lagrangian(shape(s), group(g), rotation(r))]
             fn beside(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
                 let f = q0.r.transpose() * q1.r;
                 let (ds, dg) = (q1.s - q0.s, q1.g - q0.g);
                 (Matrix3::identity() - f).trace() / h + 0.5 * m * (ds * ds + ds * dg + dg * dg) / h
             }",
        "#[reduced_lagrangian(shape(s), rotation(r), rule = left)]
             fn rolling(q: Config, v: Velocity, m: f64) -> f64 {
                 0.5 * v.r.norm_squared() + 0.5 * m * v.s * v.s
             }",
    ];
    for source in systems {
        let system = dirac_compiler::text::compile_lie(source).unwrap();
        // The stored positions, and the identity on each rotation.
        let (mut positions, mut near) = (Vec::new(), Vec::new());
        for c in &system.coordinates {
            let at = near.len();
            match c.kind.name() {
                "shape" | "group" => {
                    positions.push(at);
                    near.push(0.0);
                }
                kind => {
                    let identity = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
                    near.extend(identity);
                    if kind == "pose" {
                        positions.extend([at + 9, at + 10, at + 11]);
                        near.extend([0.0; 3]);
                    }
                }
            }
        }
        assert_eq!(near.len(), system.point_len(), "{}", system.name);
        let stepper = &system.stepper;
        let mut programs = vec![
            ("residual", &stepper.residual_jacobian),
            ("momentum", &stepper.momentum),
        ];
        programs.extend(system.partials.as_ref().map(|p| ("partials", p)));
        assert_eq!(programs.len(), 3, "{}: no partials", system.name);
        for (what, program) in programs {
            for leaf in program.leaves() {
                assert!(
                    !matches!(leaf, Leaf::Base(i) if positions.contains(&i)),
                    "{}: the {what} reads the stored position {leaf:?}",
                    system.name
                );
            }
        }
        // The values at a base point moved far along its positions are the same.
        let n = system.chart_len();
        let mut far = near.clone();
        for &i in &positions {
            far[i] = 1e8 + 0.3 * i as f64;
        }
        let z: Vec<f64> = (0..n).map(|j| 0.01 * (j as f64 + 1.0)).collect();
        let momenta: Vec<f64> = (0..n).map(|j| 0.2 - 0.03 * j as f64).collect();
        let at = |base: &[f64]| {
            stepper.residual_jacobian.eval(&|leaf| match leaf {
                Leaf::Base(i) => base[i],
                Leaf::Chart(j) => z[j],
                Leaf::P(j) => momenta[j],
                Leaf::Param(i) => 0.1 + 0.5 * i as f64,
                other => panic!("the residual read {other:?}"),
            })
        };
        assert_eq!(at(&near), at(&far), "{}", system.name);
    }
}
