//! A sharded ensemble against one process: 10⁴ members of the paper's double spherical pendulum
//! (10³ steps each, perturbed initial states and masses), run as one shard (`0/1`), then as 4
//! shards one after the other on the same cores, merged; prints both wall times, their ratio and
//! whether the merged table is the one-process table bit for bit. Progress bars on a terminal.
//!
//! ```sh
//! cargo run --release --manifest-path dirac-io/Cargo.toml --target-dir target \
//!     --example ensemble_scaling -- [--members 10000] [--steps 1000] [--shards 4] [--out target/ensemble-scaling]
//! ```
//!
//! Target (issue 22): merged = one process; 4 shards ≤ 1.1× one process.

use std::path::PathBuf;
use std::time::Instant;

use dirac_io::read::first_difference;
use dirac_io::shard::{self, Shard};

#[path = "../src/bin/dsp_ensemble/dsp.rs"]
mod dsp;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (mut members, mut steps, mut count) = (10_000, 1000, 4);
    let mut out = PathBuf::from("target/ensemble-scaling");
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().ok_or(format!("{a} needs a value"));
        match a.as_str() {
            "--members" => members = value()?.parse()?,
            "--steps" => steps = value()?.parse()?,
            "--shards" => count = value()?.parse()?,
            "--out" => out = value()?.into(),
            _ => return Err(format!("unknown argument {a}").into()),
        }
    }
    let _ = std::fs::remove_dir_all(&out);
    let table = dsp::table(members, false)?;
    println!(
        "double spherical pendulum ensemble: {members} members × {steps} steps, {} threads",
        dirac::runtime::ensemble::rayon::current_num_threads()
    );

    let t = Instant::now();
    let one = shard::run_shard(
        &table,
        Shard::new(0, 1)?,
        &out.join("one"),
        steps,
        dsp::member,
    )?;
    let one_wall = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let dir = out.join("shards");
    for i in 0..count {
        shard::run_shard(&table, Shard::new(i, count)?, &dir, steps, dsp::member)?;
    }
    let merged = out.join("merged.parquet");
    shard::merge(&dir, count, &merged)?;
    let sharded_wall = t.elapsed().as_secs_f64();

    let same = first_difference(&merged, &one.path)?;
    println!("  one process:           {one_wall:8.3} s");
    println!("  {count} shards + merge:     {sharded_wall:8.3} s");
    println!(
        "  ratio sharded / one:   {:.3} (target ≤ 1.1)",
        sharded_wall / one_wall
    );
    match same {
        None => println!("  merged table = one-process table, bit for bit"),
        Some(d) => {
            return Err(format!("merged table differs from the one-process table: {d}").into())
        }
    }
    Ok(())
}
