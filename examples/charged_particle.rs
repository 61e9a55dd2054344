//! The paper's §7.1: a charged particle in a constant magnetic field, integrated with the reduced
//! (+) equations (4.6). Prints Table 1 with the observed order of convergence and writes the
//! Figure 1 data (CSV) and figure (SVG).
//!
//! ```text
//! cargo run --release --example charged_particle [-- --out DIR]
//! ```

mod common;

use std::error::Error;

use common::charged_particle;

fn main() -> Result<(), Box<dyn Error>> {
    let out = common::output_dir(
        "charged_particle",
        "the paper's charged particle (§7.1): Table 1 and Figure 1",
        "target/dirac-figures/charged_particle",
    );
    charged_particle::print_table_1()?;
    charged_particle::write_figure_1(&out)?;
    println!("\nFigure 1 (N = 100, h = 0.2): {}", out.display());
    Ok(())
}
