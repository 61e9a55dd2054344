//! The Parquet observer and ensemble files: what is written is the run, bit for bit, under the
//! documented names; the run's description is in the metadata; memory is bounded by row groups.
//! Also writes the files the Python round trip (`tests/python/roundtrip.py`) reads back.

use std::path::{Path, PathBuf};

use dirac::paper::DoubleSphericalPendulum;
use dirac::prelude::*;
use dirac_io::read::{key_values, read_batches, read_f64_column, row_groups};
use dirac_io::{write_ensemble, Describe, EnsembleOutput, Options, ParquetObserver};

/// A fresh directory under the target directory, named after the test.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

fn dsp() -> ReducedIntegrator<DoubleSphericalPendulum, Plus, 3, 1, 4> {
    ReducedIntegrator::plus(DoubleSphericalPendulum::paper(), NewtonOptions::default())
}

/// The columns of a reduced state, in the order of the schema.
fn state_columns(s: &ReducedState<3, 1>) -> [f64; 8] {
    [
        s.x[0], s.x[1], s.x[2], s.w[0], s.w[1], s.w[2], s.mu[0], s.g[0],
    ]
}

#[test]
fn every_state_of_a_run_is_written_bit_for_bit_under_its_names() {
    let dir = scratch("every_state");
    let integ = dsp();
    let steps = 3000;
    let traj = integ
        .run(DoubleSphericalPendulum::paper_initial_state())
        .steps(steps)
        .collect()
        .unwrap();
    let path = dir.join("dsp.parquet");
    // Small row groups, so that the file has many: what is held in memory is one of them.
    let options = Options::new()
        .row_group_bytes(16 << 10)
        .extra(&["energy"], {
            let sys = DoubleSphericalPendulum::paper();
            move |_, s: &ReducedState<3, 1>, out| {
                let q = SVector::<f64, 4>::new(s.x[0], s.x[1], s.x[2], s.g[0]);
                out[0] = sys.physical_energy(&q, &q);
            }
        });
    let mut out = ParquetObserver::create(&path, integ.describe(), options).unwrap();
    let summary = integ
        .run(DoubleSphericalPendulum::paper_initial_state())
        .steps(steps)
        .observe(out.observer())
        .stream();
    assert_eq!(out.rows(), steps as u64 + 1);
    assert_eq!(out.finish_with(&summary).unwrap(), path);

    let (groups, largest) = row_groups(&path).unwrap();
    // 16 KiB of values per group: 146 rows of 14 eight-byte columns.
    assert_eq!((groups, largest), (21, 146));
    let batches = read_batches(&path).unwrap();
    let names: Vec<String> = batches[0]
        .schema()
        .fields()
        .iter()
        .map(|f| f.name().clone())
        .collect();
    assert_eq!(
        names,
        [
            "step",
            "t",
            "x_phi1",
            "x_vt2",
            "x_phi2",
            "w_phi1",
            "w_vt2",
            "w_phi2",
            "mu_vt1",
            "g_vt1",
            "iterations",
            "residual",
            "rcond",
            "energy"
        ]
    );
    let expected_columns: Vec<Vec<f64>> = (0..8)
        .map(|c| traj.states.iter().map(|s| state_columns(s)[c]).collect())
        .collect();
    for (c, name) in names[2..10].iter().enumerate() {
        let column = read_f64_column(&path, name).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&column), bits(&expected_columns[c]), "column {name}");
    }
    let t = read_f64_column(&path, "t").unwrap();
    assert_eq!(t[7].to_bits(), (7.0 * traj.h).to_bits());
    let residual = read_f64_column(&path, "residual").unwrap();
    assert!(residual[0].is_nan(), "the initial state has no step: null");
    for (k, stats) in traj.stats.iter().enumerate() {
        assert_eq!(residual[k + 1].to_bits(), stats.residual.to_bits());
    }

    let kv = key_values(&path).unwrap();
    let p = DoubleSphericalPendulum::paper();
    assert_eq!(kv["dirac.parameters"], "h,m1,m2,l1,l2,g");
    assert_eq!(kv["dirac.parameter.m2"].parse::<f64>().unwrap(), p.m2);
    assert_eq!(kv["dirac.h"].parse::<f64>().unwrap(), p.h);
    assert_eq!(
        kv["dirac.newton.max_iterations"],
        NewtonOptions::default().max_iterations.to_string()
    );
    assert_eq!(kv["dirac.shape"], "phi1,vt2,phi2");
    assert_eq!(kv["dirac.outcome"], "completed");
    assert_eq!(kv["dirac.steps"], steps.to_string());
}

#[test]
fn every_kth_state_and_the_last_one() {
    let dir = scratch("every_kth");
    let integ = dsp();
    let path = dir.join("every7.parquet");
    let mut out =
        ParquetObserver::create(&path, integ.describe(), Options::new().every(7)).unwrap();
    let result = integ
        .run(DoubleSphericalPendulum::paper_initial_state())
        .steps(100)
        .observe(out.observer())
        .stream();
    out.finish_with(&result).unwrap();
    let steps = read_batches(&path).unwrap()[0]
        .column_by_name("step")
        .unwrap()
        .as_any()
        .downcast_ref::<arrow_array::UInt64Array>()
        .unwrap()
        .values()
        .to_vec();
    let mut expected: Vec<u64> = (0..=100).step_by(7).collect();
    expected.push(100);
    assert_eq!(steps, expected);
    assert_eq!(
        read_f64_column(&path, "x_phi1")
            .unwrap()
            .last()
            .unwrap()
            .to_bits(),
        result.unwrap().last.x[0].to_bits()
    );
}

#[test]
fn canonical_states_are_named_q_and_p() {
    let dir = scratch("canonical");
    let sys = DoubleSphericalPendulum::paper();
    let integ = UnreducedIntegrator::new(sys, NewtonOptions::default());
    let start = sys.untrivialize(&DoubleSphericalPendulum::paper_initial_state());
    let path = dir.join("canonical.parquet");
    let mut out = ParquetObserver::create(&path, integ.describe(), Options::new()).unwrap();
    let summary = integ
        .run(start)
        .steps(20)
        .observe(out.observer())
        .stream()
        .unwrap();
    out.finish().unwrap();
    let schema = read_batches(&path).unwrap()[0].schema();
    let names: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
    assert_eq!(
        &names[2..10],
        ["q_phi1", "q_vt2", "q_phi2", "q_vt1", "p_phi1", "p_vt2", "p_phi2", "p_vt1"]
    );
    let last = read_f64_column(&path, "p_vt1").unwrap();
    assert_eq!(last[20].to_bits(), summary.last.p[3].to_bits());
}

/// A failed run keeps its states up to the failure, and its typed error in the metadata.
#[test]
fn a_failed_run_records_its_error() {
    let dir = scratch("failed");
    let integ = ReducedIntegrator::plus(
        DoubleSphericalPendulum::paper(),
        NewtonOptions {
            max_iterations: 1,
            ..NewtonOptions::default()
        },
    );
    let path = dir.join("failed.parquet");
    let mut out = ParquetObserver::create(&path, integ.describe(), Options::new()).unwrap();
    let result = integ
        .run(DoubleSphericalPendulum::paper_initial_state())
        .steps(50)
        .observe(out.observer())
        .stream();
    let error = result.as_ref().expect_err("one correction is not enough");
    out.finish_with(&result).unwrap();
    let kv = key_values(&path).unwrap();
    assert_eq!(kv["dirac.outcome"], "failed");
    assert_eq!(kv["dirac.error.kind"], error.source.kind());
    assert_eq!(kv["dirac.error.step"], error.source.step().to_string());
    assert_eq!(kv["dirac.error.message"], error.source.to_string());
    assert_eq!(
        read_f64_column(&path, "x_phi1").unwrap().len(),
        error.trajectory.step_count + 1
    );
}

/// An ensemble in one file (with a `member` column) holds what the per-member files hold, in
/// member order, and each member is its sequential run.
#[test]
fn ensembles_one_file_per_member_or_one_file() {
    let dir = scratch("ensemble");
    let integ = dsp();
    let start = DoubleSphericalPendulum::paper_initial_state();
    let initials: Vec<ReducedState<3, 1>> = (0..5)
        .map(|i| {
            let mut s = start;
            s.w[0] += 0.01 * i as f64;
            s
        })
        .collect();
    let info = integ.describe();
    let per = EnsembleOutput::PerMember(dir.join("members"));
    let one = EnsembleOutput::OneFile(dir.join("all.parquet"));
    let a = write_ensemble(
        &integ,
        &info,
        &initials,
        200,
        |_| Options::new().every(10),
        &per,
    )
    .unwrap();
    let b = write_ensemble(
        &integ,
        &info,
        &initials,
        200,
        |_| Options::new().every(10),
        &one,
    )
    .unwrap();
    assert_eq!(a.len(), 5);
    for (i, (ra, rb)) in a.iter().zip(&b).enumerate() {
        let sequential = integ
            .run(initials[i])
            .steps(200)
            .observe(|_, _, _, _| {})
            .stream()
            .unwrap();
        assert_eq!(ra.as_ref().unwrap(), &sequential);
        assert_eq!(rb.as_ref().unwrap(), &sequential);
    }
    assert!(
        !dir.join("all.parquet.parts").exists(),
        "the parts are removed"
    );
    let all = read_f64_column(&dir.join("all.parquet"), "w_phi1").unwrap();
    let members: Vec<f64> = (0..5)
        .flat_map(|i| {
            read_f64_column(
                &dirac_io::ensemble::member_file(&dir.join("members"), i),
                "w_phi1",
            )
            .unwrap()
        })
        .collect();
    assert_eq!(all.len(), 5 * 21);
    assert_eq!(
        all.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        members.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
    );
}

/// Writes `python-roundtrip/dsp.parquet` and the exact values it must hold, as hexadecimal
/// bit patterns, for `tests/python/roundtrip.py` (run by `.ci/run` after this test).
#[test]
fn files_for_the_python_round_trip() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("python-roundtrip");
    std::fs::create_dir_all(&dir).unwrap();
    let integ = dsp();
    let steps = 500;
    let traj = integ
        .run(DoubleSphericalPendulum::paper_initial_state())
        .steps(steps)
        .collect()
        .unwrap();
    // A directory of parts (200 rows each: 3 parts), as a run writes by default.
    let path = dir.join("dsp.parquet");
    let _ = std::fs::remove_file(&path);
    let options = Options::new()
        .row_group_bytes(100 * 14 * 8)
        .rows_per_file(200);
    let mut out = ParquetObserver::create(&path, integ.describe(), options).unwrap();
    let result = integ
        .run(DoubleSphericalPendulum::paper_initial_state())
        .steps(steps)
        .observe(out.observer())
        .stream();
    out.finish_with(&result).unwrap();
    assert_eq!(dirac_io::read::files(&path).unwrap().len(), 3);

    let hex = |v: f64| format!("\"{:016x}\"", v.to_bits());
    let list = |values: Vec<String>| format!("[{}]", values.join(","));
    let names = integ.describe().columns;
    let mut fields = Vec::new();
    fields.push(format!(
        "\"step\": {}",
        list((0..=steps).map(|k| k.to_string()).collect())
    ));
    fields.push(format!(
        "\"t\": {}",
        list((0..=steps).map(|k| hex(k as f64 * traj.h)).collect())
    ));
    for (c, name) in names.iter().enumerate() {
        let values = traj
            .states
            .iter()
            .map(|s| hex(state_columns(s)[c]))
            .collect();
        fields.push(format!("\"{name}\": {}", list(values)));
    }
    let nullable = |f: &dyn Fn(&StepStats) -> Option<String>| {
        let mut v = vec!["null".to_owned()];
        v.extend(
            traj.stats
                .iter()
                .map(|s| f(s).unwrap_or_else(|| "null".into())),
        );
        list(v)
    };
    fields.push(format!(
        "\"iterations\": {}",
        nullable(&|s| Some(s.iterations.to_string()))
    ));
    fields.push(format!(
        "\"residual\": {}",
        nullable(&|s| Some(hex(s.residual)))
    ));
    fields.push(format!("\"rcond\": {}", nullable(&|s| s.rcond.map(hex))));
    let p = DoubleSphericalPendulum::paper();
    let metadata = format!(
        "\"metadata\": {{\"dirac.parameters\": \"h,m1,m2,l1,l2,g\", \"dirac.parameter.m2\": \"{}\", \"dirac.outcome\": \"completed\"}}",
        hex(p.m2).trim_matches('"')
    );
    fields.push(metadata);
    let json = format!("{{\n{}\n}}\n", fields.join(",\n"));
    std::fs::write(dir.join("dsp.expected.json"), json).unwrap();
}

/// A run split into parts holds, part after part, exactly the rows of the same run in one file;
/// every part has the run's metadata, the last one its outcome.
#[test]
fn a_run_split_into_parts_is_the_run_in_one_file() {
    let dir = scratch("parts");
    let integ = dsp();
    let start = DoubleSphericalPendulum::paper_initial_state();
    let write = |path: &Path, options: Options<ReducedState<3, 1>>| {
        let mut out = ParquetObserver::create(path, integ.describe(), options).unwrap();
        let result = integ
            .run(start)
            .steps(1000)
            .observe(out.observer())
            .stream();
        out.finish_with(&result).unwrap()
    };
    // Row groups of 64 rows (13 columns of 8 bytes), parts of 300 rows: 5 groups each (four of
    // 64 rows, and one of 44 cut at the part's end).
    let small = || Options::new().row_group_bytes(64 * 13 * 8);
    let one = write(&dir.join("one.parquet"), small());
    let parts = write(&dir.join("parts"), small().rows_per_file(300));
    assert!(parts.is_dir());
    let mut files: Vec<PathBuf> = std::fs::read_dir(&parts)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let names: Vec<String> = files
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        [
            "part-00000.parquet",
            "part-00001.parquet",
            "part-00002.parquet",
            "part-00003.parquet"
        ]
    );
    for f in &files[..3] {
        assert_eq!(row_groups(f).unwrap(), (5, 64));
        assert_eq!(
            key_values(f).unwrap()["dirac.parameters"],
            "h,m1,m2,l1,l2,g"
        );
        assert!(!key_values(f).unwrap().contains_key("dirac.outcome"));
    }
    assert_eq!(key_values(&files[3]).unwrap()["dirac.outcome"], "completed");
    let merged = dir.join("merged.parquet");
    dirac_io::read::concatenate(&files, &merged, Vec::new()).unwrap();
    assert_eq!(
        dirac_io::read::first_difference(&merged, &one).unwrap(),
        None
    );
}

/// Parts of the rows asked for, whatever the row groups: with the default groups (80,000 rows of
/// these 13 columns) parts of 1000 rows are one group of 1000 rows each, published as each
/// fills; a run that ends with a full part ends with a part of no rows carrying its outcome, and
/// the readers take the last state from the part before.
#[test]
fn parts_hold_the_rows_asked_for_and_a_full_last_part_is_followed_by_the_outcome() {
    let dir = scratch("parts_rows");
    let integ = dsp();
    let start = DoubleSphericalPendulum::paper_initial_state();
    let path = dir.join("dsp");
    let mut out =
        ParquetObserver::create(&path, integ.describe(), Options::new().rows_per_file(1000))
            .unwrap();
    // 2999 steps: 3000 states, three full parts.
    let result = integ
        .run(start)
        .steps(2999)
        .observe(out.observer())
        .stream();
    out.finish_with(&result).unwrap();
    let files = dirac_io::read::files(&path).unwrap();
    assert_eq!(files.len(), 4);
    for f in &files[..3] {
        assert_eq!(row_groups(f).unwrap(), (1, 1000));
        assert!(!key_values(f).unwrap().contains_key("dirac.outcome"));
    }
    assert_eq!(dirac_io::read::row_count(&files[3]).unwrap(), 0);
    assert_eq!(key_values(&path).unwrap()["dirac.outcome"], "completed");
    assert_eq!(key_values(&path).unwrap()["dirac.steps"], "2999");
    assert_eq!(dirac_io::read::row_count(&path).unwrap(), 3000);
    let traj = integ.run(start).steps(2999).collect().unwrap();
    let columns = integ.describe().columns;
    let (step, t, last) =
        dirac_io::read::last_state::<ReducedState<3, 1>>(&path, &columns).unwrap();
    let times = read_f64_column(&path, "t").unwrap();
    assert_eq!((step, t, last), (2999, times[2999], traj.states[2999]));
}

/// A rigid body on `SO(3)`: every state written bit for bit, the rotation's entries and body
/// momentum under their names, and read back as the same states.
#[test]
fn rotation_states_are_written_bit_for_bit_under_their_entry_names() {
    use dirac::systems::rotations::{RigidBody, RigidBodyConfig, RigidBodyMomentum};
    use dirac_io::StateColumns;
    let dir = scratch("rotations");
    let sys = RigidBody {
        h: 0.01,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
    };
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    let start = sys.state(
        &RigidBodyConfig {
            r: dirac::lie::cayley(&Vector3::new(0.2, -0.1, 0.4)),
        },
        &RigidBodyMomentum {
            r: Vector3::new(0.3, 1.0, -0.2),
        },
    );
    let traj = integ.run(start).steps(50).collect().unwrap();
    let path = dir.join("body.parquet");
    let info = integ.describe();
    let mut out =
        ParquetObserver::create(&path, info.clone(), Options::new().single_file()).unwrap();
    let result = integ.run(start).steps(50).observe(out.observer()).stream();
    out.finish_with(&result).unwrap();
    let schema = read_batches(&path).unwrap()[0].schema();
    let names: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
    assert_eq!(
        &names[2..14],
        [
            "q_r_00", "q_r_01", "q_r_02", "q_r_10", "q_r_11", "q_r_12", "q_r_20", "q_r_21",
            "q_r_22", "p_r_x", "p_r_y", "p_r_z"
        ]
    );
    let columns: Vec<Vec<f64>> = info
        .columns
        .iter()
        .map(|c| read_f64_column(&path, c).unwrap())
        .collect();
    for (k, s) in traj.states.iter().enumerate() {
        let row: Vec<f64> = columns.iter().map(|c| c[k]).collect();
        let back = LieState::<9, 3>::read_from(&[], &row);
        assert!(
            back.q
                .iter()
                .zip(&s.q)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "state {k}"
        );
        assert!(
            back.p
                .iter()
                .zip(&s.p)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "state {k}"
        );
    }
    let kv = key_values(&path).unwrap();
    assert_eq!(kv["dirac.coordinates"], "r:rotation");
}

/// A heavy top reduced about the vertical: the reduced states, with the momentum of the
/// symmetry, written bit for bit and read back.
#[test]
fn reduced_rotation_states_are_written_bit_for_bit_with_their_momentum() {
    use dirac::systems::rotations::{HeavyTop, HeavyTopConfig, HeavyTopMomentum};
    use dirac_io::StateColumns;
    let dir = scratch("reduced-rotations");
    let sys = HeavyTop {
        h: 0.01,
        j1: 1.0,
        j2: 1.5,
        j3: 0.4,
        mgl: 2.0,
    };
    let integ = ReducedLieIntegrator::new(sys, NewtonOptions::default());
    let start = integ.reduce(&sys.state(
        &HeavyTopConfig {
            r: dirac::lie::cayley(&Vector3::new(0.6, 0.1, 0.0)),
        },
        &HeavyTopMomentum {
            r: Vector3::new(0.1, 0.3, 4.0),
        },
    ));
    let traj = integ.run(start).steps(50).collect().unwrap();
    let path = dir.join("top.parquet");
    let info = integ.describe();
    let mut out =
        ParquetObserver::create(&path, info.clone(), Options::new().single_file()).unwrap();
    let result = integ.run(start).steps(50).observe(out.observer()).stream();
    out.finish_with(&result).unwrap();
    assert_eq!(&info.columns[12..], ["mu_x", "mu_y", "mu_z"]);
    let columns: Vec<Vec<f64>> = info
        .columns
        .iter()
        .map(|c| read_f64_column(&path, c).unwrap())
        .collect();
    for (k, s) in traj.states.iter().enumerate() {
        let row: Vec<f64> = columns.iter().map(|c| c[k]).collect();
        let back = ReducedLieState::<9, 3>::read_from(&[], &row);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(back.q.as_slice()), bits(s.q.as_slice()), "state {k}");
        assert_eq!(bits(back.p.as_slice()), bits(s.p.as_slice()), "state {k}");
        assert_eq!(
            bits(back.mu.as_slice()),
            bits(start.mu.as_slice()),
            "state {k}"
        );
    }
    let kv = key_values(&path).unwrap();
    assert!(
        kv["dirac.symmetry"].contains("Axis"),
        "{:?}",
        kv["dirac.symmetry"]
    );
    assert!(kv["dirac.integrator"].starts_with("reduced"));
}

/// Kepler's problem with adaptive steps (`dt = r^{3/2} dτ`).
#[reduced_lagrangian(shape(r), group(theta, t), time(t), adapt = |q| q.r.powf(1.5), rule = midpoint)]
fn kepler(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
}

/// A spherical pendulum with adaptive steps, reduced about the vertical.
#[reduced_lagrangian(direction(n), group(t), rule = trapezoid, symmetry(n, axis = z),
    time(t), adapt = |q| 1.5 + q.n.z)]
fn swinging(q: Config, v: Velocity, g: f64) -> f64 {
    0.5 * v.n.dot(&v.n) - g * q.n.z
}

/// Adaptive runs: `dirac.physical_time` names the column of the physical time `t_k`, which is the
/// run's clock (the `t` column), written bit for bit — for an ensemble of reduced runs
/// on flat coordinates and a reduced run on a sphere.
#[test]
fn adaptive_runs_name_their_physical_time_column() {
    let dir = scratch("adaptive");
    let sys = Kepler { h: 0.05, k: 1.0 };
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    let starts: Vec<ReducedState<1, 2>> = [0.5, 0.9]
        .iter()
        .map(|&e: &f64| {
            let r0 = 1.0 - e;
            sys.reduced_state([r0, 0.0, 0.0], [0.0, (1.0 - e * e).sqrt() / (r0 * r0), 1.0])
                .unwrap()
        })
        .collect();
    let results = write_ensemble(
        &integ,
        &integ.describe(),
        &starts,
        200,
        |_| Options::new(),
        &EnsembleOutput::PerMember(dir.join("kepler")),
    )
    .unwrap();
    for (i, start) in starts.iter().enumerate() {
        assert!(results[i].is_ok());
        let path = &dirac_io::ensemble::member_file(&dir.join("kepler"), i);
        let traj = integ.run(*start).steps(200).collect().unwrap();
        let kv = key_values(path).unwrap();
        assert_eq!(kv["dirac.physical_time"], "g_t");
        let physical = read_f64_column(path, "g_t").unwrap();
        let clock = read_f64_column(path, "t").unwrap();
        assert_eq!(physical.len(), 201);
        for (k, s) in traj.states.iter().enumerate() {
            assert_eq!(physical[k].to_bits(), s.g[1].to_bits(), "state {k}");
            assert_eq!(clock[k].to_bits(), s.g[1].to_bits(), "state {k}");
        }
        // The physical steps vary along the orbit.
        let dt: Vec<f64> = physical.windows(2).map(|w| w[1] - w[0]).collect();
        let (lo, hi) = dt
            .iter()
            .fold((f64::MAX, 0.0_f64), |(l, h), &d| (l.min(d), h.max(d)));
        assert!(hi > 1.5 * lo, "{lo} {hi}");
    }

    let sys = Swinging { h: 0.02, g: 1.0 };
    let (s, c) = 1.2_f64.sin_cos();
    let start = sys
        .unreduced_state(
            &SwingingConfig {
                n: Vector3::new(s, 0.0, -c),
                t: 0.0,
            },
            &SwingingVelocity {
                n: Vector3::new(0.0, 0.8, 0.0),
                t: 1.0,
            },
        )
        .unwrap();
    let integ = ReducedLieIntegrator::new(sys, NewtonOptions::default());
    let start = integ.reduce(&start);
    let traj = integ.run(start).steps(100).collect().unwrap();
    let path = dir.join("pendulum.parquet");
    let mut out =
        ParquetObserver::create(&path, integ.describe(), Options::new().single_file()).unwrap();
    let result = integ.run(start).steps(100).observe(out.observer()).stream();
    out.finish_with(&result).unwrap();
    assert_eq!(key_values(&path).unwrap()["dirac.physical_time"], "q_t");
    let physical = read_f64_column(&path, "q_t").unwrap();
    for (k, s) in traj.states.iter().enumerate() {
        assert_eq!(physical[k].to_bits(), s.q[9].to_bits(), "state {k}");
    }
}
