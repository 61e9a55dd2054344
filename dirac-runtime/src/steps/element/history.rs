//! The memory of a run-time-sized step's last increments, from which Newton's first guess is
//! extrapolated: shared by every integrator whose configurations are `DVector`s (the
//! element-wise ones here, and integrators of other crates, such as the recursive step of
//! articulated bodies).

use nalgebra::DVector;

/// `Δ_{k−1} = q_k − q_{k−1}` and `Δ_{k−2} = q_{k−1} − q_{k−2}` with the sizes of their steps:
/// the run's memory for Newton's first guess, allocated once per run (no allocation per step).
#[derive(Clone, Debug)]
pub struct Increments {
    /// `q_k − q_{k−1}` and `q_{k−1} − q_{k−2}`, and how many of them are known (0, 1, 2).
    last: DVector<f64>,
    before: DVector<f64>,
    known: u8,
    /// The sizes of those two steps, newest first.
    steps: (f64, f64),
}

impl Increments {
    /// No increment known yet, for configurations of `n` coordinates.
    #[must_use]
    pub fn new(n: usize) -> Self {
        Self {
            last: DVector::zeros(n),
            before: DVector::zeros(n),
            known: 0,
            steps: (f64::NAN, f64::NAN),
        }
    }

    /// How many increments are known (0, 1 or 2).
    #[must_use]
    pub fn known(&self) -> usize {
        usize::from(self.known)
    }

    /// Newton's first guess for `q_{k+1}`, over a step of size `h`, into `z`: `q_k` plus the
    /// increment the last two extrapolate (`2 Δ_{k−1} − Δ_{k−2}` on a uniform grid, the
    /// quadratic through the last three points on another: `crate::stepper`'s
    /// `predicted_increment`; `Δ_{k−1}` scaled to `h` after one step; none before).
    pub fn guess(&self, q: &DVector<f64>, h: f64, z: &mut DVector<f64>) {
        z.copy_from(q);
        let (h1, h2) = self.steps;
        let same = |a: f64| a.to_bits() == h.to_bits();
        match self.known {
            0 => {}
            1 if same(h1) => *z += &self.last,
            1 => z.axpy(h / h1, &self.last, 1.0),
            _ if same(h1) && same(h2) => {
                for ((zi, l), b) in z.iter_mut().zip(self.last.iter()).zip(self.before.iter()) {
                    *zi += 2.0 * l - b;
                }
            }
            _ => {
                // Δ = h v1 + c (v1 − v2), v_i = Δ_i / h_i, c = h (h + h1) / (h1 + h2).
                let c = h * (h + h1) / (h1 + h2);
                let (a, b) = ((h + c) / h1, c / h2);
                for ((zi, l), p) in z.iter_mut().zip(self.last.iter()).zip(self.before.iter()) {
                    *zi += a * l - b * p;
                }
            }
        }
    }

    /// Records the step `q0 → q1`, of size `h`, for the next guess.
    pub fn remember(&mut self, q0: &DVector<f64>, q1: &DVector<f64>, h: f64) {
        std::mem::swap(&mut self.last, &mut self.before);
        self.last.copy_from(q1);
        self.last -= q0;
        self.steps = (h, self.steps.0);
        self.known = (self.known + 1).min(2);
    }
}
