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
//! Target: merged = one process; 4 shards ≤ 1.1× one process.

use std::path::PathBuf;
use std::time::Instant;

use dirac_io::read::first_difference;
use dirac_io::shard::{self, Shard};

#[path = "../../examples/common/cli.rs"]
mod cli;
#[path = "../src/bin/dsp_ensemble/dsp.rs"]
mod dsp;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut cli = cli::Cli::new(
        "ensemble_scaling",
        "a sharded ensemble of the double spherical pendulum against one process",
    );
    let members = cli.value(
        "--members",
        "M",
        "ensemble members",
        10_000,
        cli::at_least(1),
    );
    let steps = cli.value("--steps", "S", "steps per member", 1000, cli::at_least(1));
    let count = cli.value(
        "--shards",
        "K",
        "shards of the second run",
        4,
        cli::at_least(1),
    );
    let out = cli.value(
        "--out",
        "DIR",
        "where the shards and tables are written (emptied first)",
        PathBuf::from("target/ensemble-scaling"),
        cli::any(),
    );
    cli.finish();
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
