//! All of the paper's §7: the charged particle (§7.1: Table 1, Figure 1) and the double spherical
//! pendulum (§7.2: summary, Figure 3, top of Figure 4), written under `DIR/charged_particle` and
//! `DIR/double_spherical_pendulum`.
//!
//! ```text
//! cargo run --release --example paper [-- --out DIR]
//! ```

mod common;

use std::error::Error;

use common::{charged_particle, double_spherical_pendulum as dsp};

fn main() -> Result<(), Box<dyn Error>> {
    let out = common::output_dir(
        "paper",
        "all of the paper's §7: Table 1, Figures 1, 3, 4 and the summaries",
        "target/dirac-figures",
    );

    charged_particle::print_table_1()?;
    let dir = out.join("charged_particle");
    charged_particle::write_figure_1(&dir)?;
    println!("\nFigure 1 (N = 100, h = 0.2): {}", dir.display());

    println!("\n");
    let run = dsp::run()?;
    dsp::report(&run);
    dsp::pole_error_path();
    let dir = out.join("double_spherical_pendulum");
    dsp::write_figures(&run, &dir)?;
    println!("\nFigures 3 and 4, CSV: {}", dir.display());
    Ok(())
}
