//! The one system model ([`dirac_runtime::System`]) for a system given as text, of any family:
//! written once for the flat, rotation and element-wise systems.
//!
//! Each family's text (`dirac_compiler::text::{System, LieSystem, ElementSystem}`) declares its
//! parameters by name, the index of the time step among them and the indices of the controls;
//! each compiled system holds its parameter values first in a `values` array that its kernels
//! read. So the parameters, the time step, the system at another step and the controls are the
//! same code for every family, and only what a family knows differently (its coordinates' names,
//! its time coordinate, its domain) is passed in. A macro rather than a blanket impl: the trait
//! and the three types' fields are not a trait of this crate that a generic impl could read
//! (and the orphan rule refuses `impl<T: Local> System for T`).

/// `impl System` for a system given as text, `$ty` with fields `code` (whose `system` is the
/// family's text: `parameters`, `step`, `controls`) and `values` (the parameter values first).
/// `$sys` names `self` in the expressions that say what the family knows differently: the
/// names of its coordinates and, where the family has them, the index of its time coordinate
/// and its domain (left out: the trait's default, none).
macro_rules! impl_system {
    (
        impl[$($generics:tt)*] for $ty:ty; |$sys:ident| {
            coordinates: $coordinates:expr
            $(, time: $time:expr)?
            $(, domain: $domain:expr)? $(,)?
        }
    ) => {
        impl<$($generics)*> ::dirac_runtime::System for $ty {
            /// Empty: a system given at run time names its parameters through
            /// `parameter_names`, which is what output reads; the constant cannot know them.
            const PARAMETERS: &'static [&'static str] = &[];

            fn parameter_names(&self) -> Vec<&str> {
                self.code
                    .system
                    .parameters
                    .iter()
                    .map(String::as_str)
                    .collect()
            }

            fn parameter_values(&self) -> Vec<f64> {
                self.values[..self.code.system.parameters.len()].to_vec()
            }

            fn time_step(&self) -> f64 {
                self.values[self.code.system.step]
            }

            fn with_time_step(&self, h: f64) -> Self {
                let mut system = self.clone();
                system.values[self.code.system.step] = h;
                system
            }

            fn control_count(&self) -> usize {
                self.code.system.controls.len()
            }

            fn control_names(&self) -> Vec<&str> {
                let names = &self.code.system.parameters;
                self.code
                    .system
                    .controls
                    .iter()
                    .map(|&i| names[i].as_str())
                    .collect()
            }

            fn with_controls(&self, u: &[f64]) -> Self {
                let mut system = self.clone();
                for (&i, &v) in self.code.system.controls.iter().zip(u) {
                    system.values[i] = v;
                }
                system
            }

            $(
                /// Known from the text only: the integrators read it here, not from `TIME`.
                fn time_index(&self) -> Option<usize> {
                    let $sys = self;
                    $time
                }
            )?

            $(
                /// Known from the text only: the integrators read it here, not from `DOMAIN`.
                fn domain(&self) -> &[::dirac_runtime::domain::Bound] {
                    let $sys = self;
                    $domain
                }
            )?

            fn coordinate_names(&self) -> Vec<&str> {
                let $sys = self;
                $coordinates
            }
        }
    };
}

pub(crate) use impl_system;
