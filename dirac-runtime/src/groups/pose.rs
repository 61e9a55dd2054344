//! Rigid motions `SE(3) = SO(3) ⋉ R³` (`pose(X)`, [`Pose`]).

use nalgebra::Vector3;

use super::so3::{
    cayley, cayley_inverse, check_rotation, orthogonality_defect, rotation_from_value,
};
use super::{matrix, store_matrix, vector, CoordinateKind, Group, SpatialMomentum};

/// A pose `(R, x)`: the attitude `R ∈ SO(3)` (body → space) and the position `x ∈ R³` of a
/// rigid body, `pose(X)`.
///
/// * point: `R` row by row (9 entries), then `x` (3);
/// * chart: `(ξ, v) ∈ R⁶`, the retraction `φ_(R,x)(ξ, v) = (R cay(ξ), x + v)` — the rotation
///   left-trivialized (the body frame, as a [`So3`](super::So3) coordinate), the translation in
///   space — so `dφ(0)(η, ζ) = (R η̂, ζ)`, inverted by a sign (`cay(ξ)ᵀ = cay(−ξ)`);
/// * momentum: `(Π, p)`, the body angular momentum `Π` (`⟨P_R, R η̂⟩ = Π·η`) and the spatial
///   linear momentum `p`;
/// * spatial momentum: the momentum map of the rigid motions `(A, a)·(R, x) = (A R, A x + a)`,
///   `π = R Π + x × p` (angular) and `ℓ = p` (linear): `⟨(Π, p), ζ(q)⟩` for the generator
///   `ζ = (Rᵀ w, w × x + u)` of the motion `(ŵ, u)`, i.e. `w·π + u·ℓ`;
/// * value: the 12 entries of the point, `R` row by row then `x` (shape `(12,)`); momentum
///   value `(Π, p)` (shape `(6,)`).
#[derive(Clone, Copy, Debug, Default)]
pub struct Pose;

impl Group for Pose {
    fn name(&self) -> &'static str {
        "pose"
    }

    fn point_len(&self) -> usize {
        12
    }

    fn chart_len(&self) -> usize {
        6
    }

    /// The rotation's entries as a rotation's (`00` … `22`), then the position's `x`, `y`, `z`.
    fn point_suffixes(&self) -> &'static [&'static str] {
        &[
            "00", "01", "02", "10", "11", "12", "20", "21", "22", "x", "y", "z",
        ]
    }

    /// The body angular momentum's `ax`, `ay`, `az`, then the linear momentum's `x`, `y`, `z`
    /// (named as the position's entries it is conjugate to).
    fn chart_suffixes(&self) -> &'static [&'static str] {
        &["ax", "ay", "az", "x", "y", "z"]
    }

    fn retract(&self, q: &[f64], z: &[f64], out: &mut [f64]) {
        store_matrix(&(matrix(q) * cayley(&vector(z))), out);
        for i in 0..3 {
            out[9 + i] = q[9 + i] + z[3 + i];
        }
    }

    /// `(cay⁻¹(R_baseᵀ R), x − x_base)`, for any relative rotation by less than π.
    fn chart_inverse(&self, base: &[f64], point: &[f64], z: &mut [f64]) {
        let xi = cayley_inverse(&(matrix(base).transpose() * matrix(point)));
        z[..3].copy_from_slice(xi.as_slice());
        for i in 0..3 {
            z[3 + i] = point[9 + i] - base[9 + i];
        }
    }

    fn reproject(&self, q: &mut [f64]) {
        super::reproject_rotation(&mut q[..9]);
    }

    /// `‖RᵀR − I‖∞` of the attitude (the position is on a vector space).
    fn manifold_defect(&self, q: &[f64]) -> f64 {
        orthogonality_defect(&matrix(q))
    }

    /// The attitude a rotation, as a rotation coordinate's; the position finite.
    fn check(&self, name: &str, q: &[f64]) -> Result<(), String> {
        if !q[9..12].iter().all(|v| v.is_finite()) {
            return Err(format!(
                "the position of the pose `{name}` is not finite: ({}, {}, {})",
                q[9], q[10], q[11]
            ));
        }
        check_rotation("the rotation of the pose", name, &matrix(q))
    }

    /// `π = R Π + x × p`, `ℓ = p`.
    fn spatial_momentum(&self, q: &[f64], p: &[f64]) -> SpatialMomentum {
        let (x, linear) = (vector(&q[9..]), vector(&p[3..]));
        SpatialMomentum {
            angular: matrix(q) * vector(p) + x.cross(&linear),
            linear,
        }
    }

    /// `(Rᵀ e, e × x)`.
    fn rotation_generator(&self, q: &[f64], e: &Vector3<f64>, zeta: &mut [f64]) {
        zeta[..3].copy_from_slice((matrix(q).transpose() * e).as_slice());
        zeta[3..6].copy_from_slice(e.cross(&vector(&q[9..])).as_slice());
    }

    /// `(δΠ, δp) = (F_kᵀ r_Π + R_{k+1}ᵀ ((x_k − x_{k+1}) × r_p), r_p)` with `F_k = R_kᵀ R_{k+1}`:
    /// then `R_{k+1} δΠ + x_{k+1} × δp = R_k r_Π + x_k × r_p` and `δp = r_p`, the momentum map of
    /// `r` at `q_k`, for rotations and translations alike.
    fn carry_residual(&self, q: &[f64], q_next: &[f64], r: &[f64], p_next: &mut [f64]) {
        let (r0, r1) = (matrix(q), matrix(q_next));
        let (r_pi, r_p) = (vector(r), vector(&r[3..]));
        let moved = vector(&q[9..]) - vector(&q_next[9..]);
        let d_pi = (r0.transpose() * r1).transpose() * r_pi + r1.transpose() * moved.cross(&r_p);
        for i in 0..3 {
            p_next[i] += d_pi[i];
            p_next[3 + i] += r_p[i];
        }
    }

    fn value_shape(&self) -> &'static [usize] {
        &[12]
    }

    fn momentum_shape(&self) -> &'static [usize] {
        &[6]
    }

    fn point_from_value(&self, name: &str, value: &[f64], q: &mut [f64]) -> Result<(), String> {
        rotation_from_value(name, value, q)?;
        q[9..12].copy_from_slice(&value[9..12]);
        Ok(())
    }

    fn value(&self, q: &[f64], out: &mut Vec<f64>) {
        out.extend_from_slice(&q[..12]);
    }

    fn momentum_from_value(&self, _q: &[f64], value: &[f64], p: &mut [f64]) {
        p.copy_from_slice(&value[..6]);
    }

    fn momentum_value(&self, _q: &[f64], p: &[f64], out: &mut Vec<f64>) {
        out.extend_from_slice(&p[..6]);
    }
}

impl CoordinateKind {
    /// A rigid motion `(R, x) ∈ SE(3) = SO(3) ⋉ R³` (`pose(X)`): 12 entries of the point (`R`
    /// row by row, then `x`), 6 of the chart (the body-frame rotation, the spatial translation).
    pub const POSE: CoordinateKind = CoordinateKind(&Pose);
}

#[cfg(test)]
mod tests {
    use nalgebra::{Matrix3, Rotation3};

    use super::super::rows;
    use super::*;

    /// A pose off every axis, and a momentum with all six components.
    fn sample() -> (Vec<f64>, Vec<f64>) {
        let r = Rotation3::new(Vector3::new(0.4, -1.1, 0.7)).into_inner();
        let q: Vec<f64> = rows(&r).into_iter().chain([1.5, -0.3, 2.25]).collect();
        (q, vec![0.8, -0.2, 1.3, -0.6, 0.9, 0.35])
    }

    fn pose(q: &[f64]) -> (Matrix3<f64>, Vector3<f64>) {
        (matrix(q), vector(&q[9..]))
    }

    /// `φ_(R,x)(ξ, v) = (R cay(ξ), x + v)` entry for entry, its inverse by the chart and by a
    /// sign to round-off (a few ulps of entries of size 1).
    #[test]
    fn the_retraction_is_the_body_rotation_and_the_spatial_translation_and_inverts() {
        let (q, _) = sample();
        let z = [0.3, -0.25, 0.6, 0.5, -1.0, 0.125];
        let mut moved = vec![0.0; 12];
        Pose.retract(&q, &z, &mut moved);
        let (r, x) = pose(&q);
        let (r1, x1) = pose(&moved);
        assert!((r1 - r * cayley(&Vector3::new(0.3, -0.25, 0.6))).amax() < 1e-15);
        assert_eq!(x1, x + Vector3::new(0.5, -1.0, 0.125));
        let mut back = vec![0.0; 6];
        Pose.chart_inverse(&q, &moved, &mut back);
        for (b, z) in back.iter().zip(z) {
            assert!((b - z).abs() < 1e-14, "{back:?}");
        }
        let minus: Vec<f64> = z.iter().map(|v| -v).collect();
        let mut home = vec![0.0; 12];
        Pose.retract(&moved, &minus, &mut home);
        for (h, q) in home.iter().zip(&q) {
            assert!((h - q).abs() < 1e-14, "{home:?}");
        }
        assert!(Pose.check("X", &moved).is_ok());
    }

    /// The momentum map is equivariant, `J((A, a)·(q, p)) = Ad*_(A,a)⁻¹ J(q, p)`: under
    /// `(R, x) ↦ (A R, A x + a)` the body `Π` is unchanged and the spatial `p` turns to `A p`,
    /// and then `π' = A π + a × A ℓ`, `ℓ' = A ℓ`, computed here directly from the moved pose.
    #[test]
    fn the_momentum_map_moves_under_a_rigid_motion_as_the_coadjoint_action() {
        let (q, p) = sample();
        let j = Pose.spatial_momentum(&q, &p);
        let (r, x) = pose(&q);
        let pl = vector(&p[3..]);
        // Direct: the angular momentum about the origin of the body `R Π` plus that of its
        // centre moving with momentum `p`.
        assert!((j.angular - (r * vector(&p) + x.cross(&pl))).amax() < 1e-15);
        assert_eq!(j.linear, pl);
        let a = Rotation3::new(Vector3::new(-0.9, 0.2, 0.5)).into_inner();
        let shift = Vector3::new(0.7, 3.0, -1.25);
        let moved: Vec<f64> = rows(&(a * r))
            .into_iter()
            .chain((a * x + shift).iter().copied())
            .collect();
        let ap = a * pl;
        let moved_p = [p[0], p[1], p[2], ap.x, ap.y, ap.z];
        let j1 = Pose.spatial_momentum(&moved, &moved_p);
        assert!((j1.angular - (a * j.angular + shift.cross(&(a * j.linear)))).amax() < 1e-14);
        assert!((j1.linear - a * j.linear).amax() < 1e-15);
    }

    /// The generator of the rotation about `e` is the derivative of the chart coordinates of
    /// `exp(t ê)·q` (central differences, step 1e-5: truncation ~1e-10), and its pairing with the
    /// momentum is `e·π`.
    #[test]
    fn the_rotation_generator_is_the_derivative_of_the_turned_pose_and_pairs_to_pi() {
        let (q, p) = sample();
        let (r, x) = pose(&q);
        let pi = Pose.spatial_momentum(&q, &p).angular;
        for e in [Vector3::x(), Vector3::y(), Vector3::z()] {
            let turned = |t: f64| -> Vec<f64> {
                let g = Rotation3::new(e * t).into_inner();
                rows(&(g * r))
                    .into_iter()
                    .chain((g * x).iter().copied())
                    .collect()
            };
            let d = 1e-5;
            let (mut plus, mut minus) = (vec![0.0; 6], vec![0.0; 6]);
            Pose.chart_inverse(&q, &turned(d), &mut plus);
            Pose.chart_inverse(&q, &turned(-d), &mut minus);
            let mut zeta = vec![0.0; 6];
            Pose.rotation_generator(&q, &e, &mut zeta);
            for i in 0..6 {
                let fd = (plus[i] - minus[i]) / (2.0 * d);
                assert!((fd - zeta[i]).abs() < 1e-9, "{i}: {fd} vs {}", zeta[i]);
            }
            let pairing: f64 = zeta.iter().zip(&p).map(|(a, b)| a * b).sum();
            assert!((pairing - e.dot(&pi)).abs() < 1e-14);
        }
    }

    /// The residual carried from `q` to `q_next` moves both parts of the momentum map by those
    /// of the residual at `q`.
    #[test]
    fn a_carried_residual_moves_the_momentum_map_by_its_own() {
        let (q, p) = sample();
        let mut next = vec![0.0; 12];
        Pose.retract(&q, &[0.2, 0.1, -0.3, 0.4, 0.0, -0.7], &mut next);
        let r = [1e-9, -2e-9, 3e-9, 4e-9, -1e-9, 2e-9];
        let mut carried = p.clone();
        Pose.carry_residual(&q, &next, &r, &mut carried);
        let moved = Pose.spatial_momentum(&next, &carried);
        let before = Pose.spatial_momentum(&next, &p);
        let own = Pose.spatial_momentum(&q, &r);
        assert!((moved.angular - before.angular - own.angular).amax() < 1e-15);
        assert!((moved.linear - before.linear - own.linear).amax() < 1e-15);
    }

    #[test]
    fn a_pose_whose_attitude_is_not_a_rotation_is_refused_by_name() {
        let (mut q, _) = sample();
        q[0] *= 1.001;
        let reason = Pose.check("X", &q).unwrap_err();
        assert!(reason.contains("the rotation of the pose `X`"), "{reason}");
        let (mut q, _) = sample();
        q[10] = f64::NAN;
        assert!(Pose.check("X", &q).unwrap_err().contains("position"));
        let mut stored = vec![0.0; 12];
        let mut value = sample().0;
        value[4] = 2.0;
        assert!(Pose.point_from_value("X", &value, &mut stored).is_err());
    }
}
