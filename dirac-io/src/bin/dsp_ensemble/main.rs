//! An ensemble of the paper's double spherical pendulum (§7.2.2), sharded: the program the Slurm
//! example (`examples/slurm/ensemble.sbatch`) submits, and the pattern for one's own system —
//! only `member` below is specific to the pendulum.
//!
//! ```sh
//! dsp-ensemble table --members 10000 --out table.csv [--failing]
//! dsp-ensemble shard --table table.csv --out shards --steps 1000 --shard 2/4 [--every 10]
//! dsp-ensemble shard --table table.csv --out shards --steps 1000 --shards 4   # index from SLURM_ARRAY_TASK_ID
//! dsp-ensemble merge --out shards --shards 4 --to merged.parquet
//! dsp-ensemble compare merged.parquet one-process/shard-00000-of-00001.parquet
//! ```
//!
//! With `--every K`, a shard also writes its members' trajectories (every K-th state) to
//! `shard-…states.parquet`, and `merge` concatenates them into `merged.states.parquet`.
//!
//! `table` writes members that perturb the paper's initial state (`x_phi1`, `w_phi1`, `w_vt2`,
//! `mu_vt1`) and the second mass (`m2`); with `--failing`, member 1 gets an iteration cap of 1
//! (`max_iterations`) and member 2 a NaN shape, so that their failures are recorded.

use std::path::PathBuf;
use std::process::ExitCode;

use dirac_io::read::first_difference;
mod dsp;

use dirac_io::shard::{self, Shard, Table};
use dirac_io::Error;
use dsp::{member, table};

const USAGE: &str = "usage:
  dsp-ensemble table --members N --out FILE [--failing]
  dsp-ensemble shard --table FILE --out DIR --steps N [--every K] (--shard i/n | --shards n | [SLURM_ARRAY_TASK_ID/COUNT])
  dsp-ensemble merge --out DIR --shards n --to FILE
  dsp-ensemble compare A.parquet B.parquet";

struct Args(Vec<String>);

impl Args {
    fn value(&self, flag: &str) -> Option<&str> {
        let i = self.0.iter().position(|a| a == flag)?;
        self.0.get(i + 1).map(String::as_str)
    }

    fn required(&self, flag: &str) -> Result<&str, Error> {
        self.value(flag)
            .ok_or_else(|| Error::Usage(format!("{flag} is required\n{USAGE}")))
    }

    fn number(&self, flag: &str) -> Result<Option<usize>, Error> {
        self.value(flag)
            .map(|v| {
                v.parse().map_err(|_| {
                    Error::Usage(format!("{flag}: `{v}` is not a non-negative integer"))
                })
            })
            .transpose()
    }

    fn flag(&self, flag: &str) -> bool {
        self.0.iter().any(|a| a == flag)
    }
}

fn run() -> Result<(), Error> {
    let mut all = std::env::args().skip(1);
    let command = all.next().unwrap_or_default();
    let args = Args(all.collect());
    match command.as_str() {
        "table" => {
            let members = args
                .number("--members")?
                .ok_or_else(|| Error::Usage(format!("--members is required\n{USAGE}")))?;
            let out = PathBuf::from(args.required("--out")?);
            table(members, args.flag("--failing"))?.write(&out)?;
            println!("{members} members written to {}", out.display());
        }
        "shard" => {
            let table = Table::read(args.required("--table")?)?;
            let dir = PathBuf::from(args.required("--out")?);
            let steps = args
                .number("--steps")?
                .ok_or_else(|| Error::Usage(format!("--steps is required\n{USAGE}")))?;
            let shard = match args.value("--shard") {
                Some(s) => Shard::parse(s)?,
                None => Shard::from_slurm(args.number("--shards")?)?,
            };
            let members = shard.members(table.len());
            // Flushed at once: a test (or an operator) watching the log knows the shard started.
            eprintln!(
                "shard {}/{}: members {}..{} of {}, {steps} steps each",
                shard.index,
                shard.count,
                members.start,
                members.end,
                table.len()
            );
            let every = args.number("--every")?;
            let report = shard::run_shard_with_states(&table, shard, &dir, steps, every, member)?;
            if let Some(why) = &report.corrupt {
                println!(
                    "{}: found corrupt, run again ({why})",
                    report.path.display()
                );
            }
            if report.skipped {
                println!("{}: already complete, skipped", report.path.display());
            } else {
                println!(
                    "{}: {} members, {} failed",
                    report.path.display(),
                    report.members.len(),
                    report.failed
                );
            }
        }
        "merge" => {
            let dir = PathBuf::from(args.required("--out")?);
            let count = args
                .number("--shards")?
                .ok_or_else(|| Error::Usage(format!("--shards is required\n{USAGE}")))?;
            let to = PathBuf::from(args.required("--to")?);
            let report = shard::merge(&dir, count, &to)?;
            println!("{}: {} members", report.path.display(), report.rows);
        }
        "compare" => {
            let (Some(a), Some(b)) = (args.0.first(), args.0.get(1)) else {
                return Err(Error::Usage(USAGE.into()));
            };
            match first_difference(a.as_ref(), b.as_ref())? {
                None => println!("identical: {a} and {b} hold the same values bit for bit"),
                Some(d) => return Err(Error::Usage(format!("{a} and {b} differ: {d}"))),
            }
        }
        _ => return Err(Error::Usage(USAGE.into())),
    }
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("dsp-ensemble: {e}");
            ExitCode::FAILURE
        }
    }
}
