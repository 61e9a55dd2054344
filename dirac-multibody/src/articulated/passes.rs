//! The two passes over the tree (module documentation of [`super`]): from the root, poses,
//! axes, velocities and each body's momentum and weight; from the leaves, their subtree sums and
//! `∂L/∂v`, `∂L/∂q`. Straight f64 code over buffers allocated once per run.

use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

use super::solver::MassOperator;
use super::ArticulatedIntegrator;
use crate::pose::{axis_angle, skew};

/// The buffers of the two passes, allocated once per run.
#[derive(Clone, Debug)]
pub(super) struct Kinematics {
    /// Body poses in the world at `q̄`.
    rotation: Vec<Matrix3<f64>>,
    position: Vec<Vector3<f64>>,
    /// Spatial velocities `V_b` at the world origin.
    velocity: Vec<Vector6<f64>>,
    /// Each joint's motion subspace `S` (indexed by joint).
    axis: Vec<Vector6<f64>>,
    /// Composite spatial momenta `H_b` and weight wrenches `W_b`.
    momentum: Vec<Vector6<f64>>,
    weight: Vec<Vector6<f64>>,
    /// The potential energy at `q̄`.
    pub(super) potential: f64,
    /// `q̄` and `v` of the last midpoint pass.
    mean: Vec<f64>,
    pub(super) rate: Vec<f64>,
}

/// The motion cross product `a × b` of spatial motion vectors `(ω; v)` (Featherstone §2.9).
fn cross_motion(a: &Vector6<f64>, b: &Vector6<f64>) -> Vector6<f64> {
    let (aw, av) = (a.fixed_rows::<3>(0), a.fixed_rows::<3>(3));
    let (bw, bv) = (b.fixed_rows::<3>(0), b.fixed_rows::<3>(3));
    let w = aw.cross(&bw);
    let v = aw.cross(&bv) + av.cross(&bw);
    Vector6::new(w.x, w.y, w.z, v.x, v.y, v.z)
}

fn spatial(angular: Vector3<f64>, linear: Vector3<f64>) -> Vector6<f64> {
    Vector6::new(
        angular.x, angular.y, angular.z, linear.x, linear.y, linear.z,
    )
}

/// The spatial inertia at the world origin of a body of mass `m`, centre of mass `c` and
/// rotational inertia `ic` about it, all in world axes (Featherstone §2.13).
pub(super) fn spatial_inertia(m: f64, c: &Vector3<f64>, ic: &Matrix3<f64>) -> Matrix6<f64> {
    let cx = skew(c);
    let mut out = Matrix6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(ic + cx * cx.transpose() * m));
    out.fixed_view_mut::<3, 3>(0, 3).copy_from(&(cx * m));
    out.fixed_view_mut::<3, 3>(3, 0)
        .copy_from(&(cx.transpose() * m));
    out.fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&(Matrix3::identity() * m));
    out
}

impl Kinematics {
    pub(super) fn new(bodies: usize) -> Self {
        Self {
            rotation: vec![Matrix3::identity(); bodies],
            position: vec![Vector3::zeros(); bodies],
            velocity: vec![Vector6::zeros(); bodies],
            axis: vec![Vector6::zeros(); bodies.saturating_sub(1)],
            momentum: vec![Vector6::zeros(); bodies],
            weight: vec![Vector6::zeros(); bodies],
            potential: 0.0,
            mean: vec![0.0; bodies.saturating_sub(1)],
            rate: vec![0.0; bodies.saturating_sub(1)],
        }
    }

    /// [`Self::evaluate`] at the midpoint of the step `q0 → q1` of size `h`:
    /// `q̄ = (q0 + q1)/2`, `v = (q1 − q0)/h`.
    pub(super) fn midpoint(
        &mut self,
        integ: &ArticulatedIntegrator,
        q0: &[f64],
        q1: &[f64],
        h: f64,
        mass: Option<&mut MassOperator>,
    ) {
        let (mut mean, mut rate) = (
            std::mem::take(&mut self.mean),
            std::mem::take(&mut self.rate),
        );
        for (j, (a, b)) in q0.iter().zip(q1).enumerate() {
            mean[j] = 0.5 * (a + b);
            rate[j] = (b - a) / h;
        }
        self.evaluate(integ, &mean, &rate, mass);
        (self.mean, self.rate) = (mean, rate);
    }

    /// The pass from the root at configuration `q` and rates `v`: poses, axes, velocities, each
    /// body's momentum and weight (not yet summed), the potential; with `mass`, each body's
    /// spatial inertia and the axes for the articulated-body solve.
    pub(super) fn evaluate(
        &mut self,
        integ: &ArticulatedIntegrator,
        q: &[f64],
        v: &[f64],
        mut mass: Option<&mut MassOperator>,
    ) {
        let g = integ.gravity;
        let root = &integ.bodies[0];
        self.potential = -root.mass * g.dot(&root.com);
        self.momentum[0] = Vector6::zeros();
        self.weight[0] = Vector6::zeros();
        if let Some(mass) = mass.as_deref_mut() {
            mass.inertia[0] = spatial_inertia(root.mass, &root.com, &root.inertia);
        }
        for (j, joint) in integ.joints.iter().enumerate() {
            let (rl, pl) = (self.rotation[joint.parent], self.position[joint.parent]);
            let rj = rl * joint.placement.rotation;
            let pj = pl + rl * joint.placement.translation;
            let a = rj * joint.axis;
            let (r, p, s) = if joint.prismatic {
                let p = pj + a * q[j];
                (rj, p, spatial(Vector3::zeros(), a))
            } else {
                let r = rj * axis_angle(&joint.axis, q[j]);
                (r, pj, spatial(a, pj.cross(&a)))
            };
            let c = joint.child;
            let vel = self.velocity[joint.parent] + s * v[j];
            let body = &integ.bodies[c];
            let com = r * body.com + p;
            let ic = r * body.inertia * r.transpose();
            let omega = vel.fixed_rows::<3>(0).into_owned();
            let v_com = vel.fixed_rows::<3>(3) + omega.cross(&com);
            let linear = v_com * body.mass;
            self.momentum[c] = spatial(ic * omega + com.cross(&linear), linear);
            let weight = g * body.mass;
            self.weight[c] = spatial(com.cross(&weight), weight);
            self.potential -= weight.dot(&com);
            self.rotation[c] = r;
            self.position[c] = p;
            self.velocity[c] = vel;
            self.axis[j] = s;
            if let Some(mass) = mass.as_deref_mut() {
                mass.inertia[c] = spatial_inertia(body.mass, &com, &ic);
                mass.axis[j] = s;
            }
        }
    }

    /// The pass from the leaves: the subtree sums, then `∂L/∂v` into `lv` and (with `lq`)
    /// `∂L/∂q` (module documentation).
    pub(super) fn momenta(
        &mut self,
        integ: &ArticulatedIntegrator,
        mut lq: Option<&mut [f64]>,
        lv: &mut [f64],
    ) {
        for (j, joint) in integ.joints.iter().enumerate().rev() {
            let (c, parent) = (joint.child, joint.parent);
            let s = &self.axis[j];
            let hc = self.momentum[c];
            let wc = self.weight[c];
            lv[j] = s.dot(&hc);
            if let Some(lq) = lq.as_deref_mut() {
                lq[j] = hc.dot(&cross_motion(&self.velocity[parent], s)) + wc.dot(s);
            }
            self.momentum[parent] += hc;
            self.weight[parent] += wc;
        }
    }
}

/// The passes' buffers with `∂L/∂q` and `∂L/∂v`: what one evaluation of the step residual
/// needs, in the step and in the corrections' products alike.
#[derive(Clone, Debug)]
pub(super) struct Passes {
    pub(super) kinematics: Kinematics,
    pub(super) lq: Vec<f64>,
    pub(super) lv: Vec<f64>,
}

/// What a step's residual reads besides `q_{k+1}`: `q_k`, `p_k`, the torques `τ_k` and `h`.
#[derive(Clone, Copy, Debug)]
pub(super) struct StepData<'a> {
    pub(super) q0: &'a [f64],
    pub(super) p0: &'a [f64],
    pub(super) torque: &'a [f64],
    pub(super) h: f64,
}

impl Passes {
    pub(super) fn new(integ: &ArticulatedIntegrator) -> Self {
        let n = integ.dim();
        Self {
            kinematics: Kinematics::new(n + 1),
            lq: vec![0.0; n],
            lv: vec![0.0; n],
        }
    }

    /// `R(q1) = p_k + (h/2)(L_q + τ_k) − L_v` into `r`, with the mass operator at `q̄` when
    /// asked; `lq` and `lv` keep `L_q`, `L_v` of this point.
    pub(super) fn residual(
        &mut self,
        integ: &ArticulatedIntegrator,
        data: &StepData<'_>,
        q1: &[f64],
        r: &mut [f64],
        mass: Option<&mut MassOperator>,
    ) {
        self.kinematics.midpoint(integ, data.q0, q1, data.h, mass);
        self.kinematics
            .momenta(integ, Some(&mut self.lq), &mut self.lv);
        for (j, rj) in r.iter_mut().enumerate() {
            *rj = data.p0[j] + 0.5 * data.h * (self.lq[j] + data.torque[j]) - self.lv[j];
        }
    }
}
