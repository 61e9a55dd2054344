//! The measurements page, `BENCHMARKS.md` in the source: each table with the command that makes
//! it, the date it was measured and the machine.
#![doc = include_str!("../../BENCHMARKS.md")]
