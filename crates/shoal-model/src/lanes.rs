//! Classic RK4 for `N` hulls at once, as structure of arrays: every quantity is an array of
//! `N` lanes (one per hull), and each stage walks the lanes in one loop with no branches, so
//! the compiler turns it into vector instructions (two or four hulls per instruction,
//! depending on the target). The constants of the equation of motion ([`DynConsts`]: M⁻¹,
//! M_A, the restoring terms, damping) are prepared once per group of hulls that share them —
//! in a swarm, every vehicle of a kind whose ballast is the initial one. Hulls of different
//! models (a model search replaying one log for several parameter vectors) step together with
//! one set of constants per lane ([`LaneConsts`]).
//!
//! Every lane does exactly the same floating-point operations in the same order whatever `N`
//! and whichever other hulls share its group, so one hull integrated alone (`N = 1`, as
//! `dynamics::integrate` does) and in a group of four give bit-identical results —
//! which is what keeps a world's result independent of how its vehicles are chunked over
//! threads.
//!
//! The equation of motion is the one of [`crate::rigid_body`] (relative-velocity form,
//! constant current):
//!
//! ```text
//! ṗ = R(q) v_r + v_c,  q̇ = ½ q ⊗ (0, ω),  M ν̇_r = τ − C_RB(ν_r)ν_r − C_A(ν_r)ν_r − D(ν_r)ν_r − g(η)
//! ```
//!
//! The attitude inside a step is the RK4 stage quaternion, not renormalised: R(q) is
//! evaluated as the rotation of q/|q| (each term of R is quadratic in q, so the division by
//! |q|² replaces the square root of a normalisation).

use crate::math::{Quat, Vec3, Vec6};
use crate::rigid_body::{BodyParams, Environment, MassProperties, RigidState};
use nalgebra::Quaternion;

/// Hulls per group in a swarm step.
pub const LANES: usize = 4;

/// A constant of the equation of motion as the lane kernel reads it for lane `l` of `N`:
/// one value for every lane (`f64`, a swarm's group of hulls of one kind) or one value per
/// lane (`[f64; N]`, hulls of different models stepped together). The kernel does the same
/// operations either way; only where it loads the constant from differs.
pub trait PerLane<const N: usize>: Copy {
    /// The value for lane `l` (< `N`).
    fn at(&self, l: usize) -> f64;
}

impl<const N: usize> PerLane<N> for f64 {
    #[inline(always)]
    fn at(&self, _l: usize) -> f64 {
        *self
    }
}

impl<const N: usize> PerLane<N> for [f64; N] {
    #[inline(always)]
    fn at(&self, l: usize) -> f64 {
        self[l]
    }
}

/// The constants of the equation of motion in the form the lane kernel uses, each stored as
/// `S` ([`PerLane`]): [`DynConsts`] for one hull kind in one ballast state and one water,
/// [`LaneConsts`] for a different set in each lane.
#[derive(Clone, Debug, PartialEq)]
pub struct Consts<S> {
    /// Total mass m \[kg\].
    mass: S,
    /// Centre of gravity, body frame \[m\].
    cog: [S; 3],
    /// Centre of buoyancy, body frame \[m\].
    cob: [S; 3],
    /// Rigid-body inertia about the body origin, row-major [kg·m²].
    inertia: [[S; 3]; 3],
    /// Added-mass matrix M_A, row-major [kg, kg·m, kg·m²].
    added: [[S; 6]; 6],
    /// M⁻¹, row-major.
    m_inv: [[S; 6]; 6],
    /// Linear damping [N·s/m, N·m·s].
    d_lin: [S; 6],
    /// Quadratic damping [N·s²/m², N·m·s²].
    d_quad: [S; 6],
    /// Weight m g \[N\].
    weight: S,
    /// Buoyancy when fully submerged ρ g V \[N\].
    buoyancy: S,
    /// Half the hull height \[m\].
    half_h: S,
    /// 1 / hull height [1/m].
    inv_h: S,
    /// Water current, world frame [m/s].
    current: [S; 3],
}

/// The constants of the equation of motion of one hull kind in one ballast state and one
/// water, shared by every lane.
pub type DynConsts = Consts<f64>;

/// One set of constants of the equation of motion per lane: `N` hulls of different models
/// (or ballast states, or waters) stepped together.
pub type LaneConsts<const N: usize> = Consts<[f64; N]>;

fn arr3(v: &Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

impl DynConsts {
    /// The constants of `body` with mass properties `mp` in the water `env`.
    pub fn new(body: &BodyParams, mp: &MassProperties, env: &Environment) -> Self {
        let h = body.hull_size.z.max(1e-6);
        Self {
            mass: mp.mass,
            cog: arr3(&mp.cog),
            cob: arr3(&body.cob),
            inertia: std::array::from_fn(|i| std::array::from_fn(|j| mp.inertia_origin[(i, j)])),
            added: std::array::from_fn(|i| std::array::from_fn(|j| body.added_mass[(i, j)])),
            m_inv: std::array::from_fn(|i| std::array::from_fn(|j| mp.m_inv[(i, j)])),
            d_lin: std::array::from_fn(|i| body.damping_linear[i]),
            d_quad: std::array::from_fn(|i| body.damping_quadratic[i]),
            weight: mp.mass * env.gravity,
            buoyancy: env.density * env.gravity * body.volume,
            half_h: 0.5 * h,
            inv_h: 1.0 / h,
            current: arr3(&env.current),
        }
    }
}

impl<const N: usize> LaneConsts<N> {
    /// `c` in every lane.
    pub fn splat(c: &DynConsts) -> Self {
        fn each<const K: usize, const N: usize>(a: &[f64; K]) -> [[f64; N]; K] {
            a.map(|v| [v; N])
        }
        Self {
            mass: [c.mass; N],
            cog: each(&c.cog),
            cob: each(&c.cob),
            inertia: c.inertia.each_ref().map(each),
            added: c.added.each_ref().map(each),
            m_inv: c.m_inv.each_ref().map(each),
            d_lin: each(&c.d_lin),
            d_quad: each(&c.d_quad),
            weight: [c.weight; N],
            buoyancy: [c.buoyancy; N],
            half_h: [c.half_h; N],
            inv_h: [c.inv_h; N],
            current: each(&c.current),
        }
    }

    /// Puts `c` into lane `l`.
    pub fn set(&mut self, l: usize, c: &DynConsts) {
        fn each<const K: usize, const N: usize>(to: &mut [[f64; N]; K], from: &[f64; K], l: usize) {
            for (t, f) in to.iter_mut().zip(from) {
                t[l] = *f;
            }
        }
        self.mass[l] = c.mass;
        each(&mut self.cog, &c.cog, l);
        each(&mut self.cob, &c.cob, l);
        for (t, f) in self.inertia.iter_mut().zip(&c.inertia) {
            each(t, f, l);
        }
        for (t, f) in self.added.iter_mut().zip(&c.added) {
            each(t, f, l);
        }
        for (t, f) in self.m_inv.iter_mut().zip(&c.m_inv) {
            each(t, f, l);
        }
        each(&mut self.d_lin, &c.d_lin, l);
        each(&mut self.d_quad, &c.d_quad, l);
        self.weight[l] = c.weight;
        self.buoyancy[l] = c.buoyancy;
        self.half_h[l] = c.half_h;
        self.inv_h[l] = c.inv_h;
        each(&mut self.current, &c.current, l);
    }
}

/// Pose, velocity and applied force of `N` hulls, one lane each.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lanes<const N: usize> {
    /// Position, world frame: x, y, z \[m\].
    pub p: [[f64; N]; 3],
    /// Attitude quaternion: w, x, y, z.
    pub q: [[f64; N]; 4],
    /// Velocity relative to the water, body frame (u, v, w [m/s], p, q, r [rad/s]).
    pub nu: [[f64; N]; 6],
    /// Applied force, body frame, held over the step [N, N·m].
    pub tau: [[f64; N]; 6],
}

impl<const N: usize> Default for Lanes<N> {
    fn default() -> Self {
        Self {
            p: [[0.0; N]; 3],
            q: [[1.0; N], [0.0; N], [0.0; N], [0.0; N]],
            nu: [[0.0; N]; 6],
            tau: [[0.0; N]; 6],
        }
    }
}

impl<const N: usize> Lanes<N> {
    /// Puts `state` and force `tau` [N, N·m] into lane `l`.
    #[inline]
    pub fn load(&mut self, l: usize, state: &RigidState, tau: &Vec6) {
        for k in 0..3 {
            self.p[k][l] = state.position[k];
        }
        let q = state.attitude.quaternion();
        self.q[0][l] = q.w;
        self.q[1][l] = q.i;
        self.q[2][l] = q.j;
        self.q[3][l] = q.k;
        for k in 0..6 {
            self.nu[k][l] = state.nu[k];
            self.tau[k][l] = tau[k];
        }
    }

    /// Writes lane `l` back into `state` (the attitude as stored: already normalised by
    /// [`rk4`]).
    #[inline]
    pub fn store(&self, l: usize, state: &mut RigidState) {
        state.position = Vec3::new(self.p[0][l], self.p[1][l], self.p[2][l]);
        state.attitude = Quat::new_unchecked(Quaternion::new(
            self.q[0][l],
            self.q[1][l],
            self.q[2][l],
            self.q[3][l],
        ));
        state.nu = Vec6::from_fn(|k, _| self.nu[k][l]);
    }
}

/// Time derivatives of one stage.
struct Deriv<const N: usize> {
    p: [[f64; N]; 3],
    q: [[f64; N]; 4],
    nu: [[f64; N]; 6],
}

#[inline(always)]
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The derivatives at a stage state (position only through its depth).
#[inline(always)]
#[expect(
    clippy::needless_range_loop,
    reason = "rows of R and lanes indexed together, written as the equations read"
)]
fn deriv<const N: usize, S: PerLane<N>>(
    c: &Consts<S>,
    pz: &[f64; N],
    q: &[[f64; N]; 4],
    nu: &[[f64; N]; 6],
    tau: &[[f64; N]; 6],
) -> Deriv<N> {
    let mut d = Deriv {
        p: [[0.0; N]; 3],
        q: [[0.0; N]; 4],
        nu: [[0.0; N]; 6],
    };
    for l in 0..N {
        let at3 = |a: &[S; 3]| [a[0].at(l), a[1].at(l), a[2].at(l)];
        let (cog, cob) = (at3(&c.cog), at3(&c.cob));
        let (qw, qx, qy, qz) = (q[0][l], q[1][l], q[2][l], q[3][l]);
        let s = 2.0 / (qw * qw + qx * qx + qy * qy + qz * qz);
        // Rotation body → world of q/|q|.
        let (xx, yy, zz) = (qx * qx * s, qy * qy * s, qz * qz * s);
        let (xy, xz, yz) = (qx * qy * s, qx * qz * s, qy * qz * s);
        let (wx, wy, wz) = (qw * qx * s, qw * qy * s, qw * qz * s);
        let r = [
            [1.0 - (yy + zz), xy - wz, xz + wy],
            [xy + wz, 1.0 - (xx + zz), yz - wx],
            [xz - wy, yz + wx, 1.0 - (xx + yy)],
        ];
        let v = [nu[0][l], nu[1][l], nu[2][l]];
        let w = [nu[3][l], nu[4][l], nu[5][l]];
        for k in 0..3 {
            d.p[k][l] = r[k][0] * v[0] + r[k][1] * v[1] + r[k][2] * v[2] + c.current[k].at(l);
        }
        // q̇ = ½ q ⊗ (0, ω).
        d.q[0][l] = -0.5 * (qx * w[0] + qy * w[1] + qz * w[2]);
        d.q[1][l] = 0.5 * (qw * w[0] + qy * w[2] - qz * w[1]);
        d.q[2][l] = 0.5 * (qw * w[1] + qz * w[0] - qx * w[2]);
        d.q[3][l] = 0.5 * (qw * w[2] + qx * w[1] - qy * w[0]);
        // Restoring: the world's down axis in the body frame is the last row of R.
        let down = r[2];
        let depth_cob = pz[l] + down[0] * cob[0] + down[1] * cob[1] + down[2] * cob[2];
        let frac = ((depth_cob + c.half_h.at(l)) * c.inv_h.at(l)).clamp(0.0, 1.0);
        let buoy = c.buoyancy.at(l) * frac;
        let weight = c.weight.at(l);
        let net = weight - buoy;
        let arm = [
            weight * cog[0] - buoy * cob[0],
            weight * cog[1] - buoy * cob[1],
            weight * cog[2] - buoy * cob[2],
        ];
        let g_t = cross(arm, down);
        // C_RB(ν)ν, linear-velocity-independent form.
        let m = c.mass.at(l);
        let wv = cross(w, v);
        let wwg = cross(w, cross(w, cog));
        let i = &c.inertia;
        let iw = [
            i[0][0].at(l) * w[0] + i[0][1].at(l) * w[1] + i[0][2].at(l) * w[2],
            i[1][0].at(l) * w[0] + i[1][1].at(l) * w[1] + i[1][2].at(l) * w[2],
            i[2][0].at(l) * w[0] + i[2][1].at(l) * w[1] + i[2][2].at(l) * w[2],
        ];
        let g_wv = cross(cog, wv);
        let w_iw = cross(w, iw);
        // C_A(ν)ν for a symmetric M_A.
        let nul = [v[0], v[1], v[2], w[0], w[1], w[2]];
        let mut a = [0.0; 6];
        for (i, ai) in a.iter_mut().enumerate() {
            let row = &c.added[i];
            *ai = row[0].at(l) * nul[0]
                + row[1].at(l) * nul[1]
                + row[2].at(l) * nul[2]
                + row[3].at(l) * nul[3]
                + row[4].at(l) * nul[4]
                + row[5].at(l) * nul[5];
        }
        let a1 = [a[0], a[1], a[2]];
        let a2 = [a[3], a[4], a[5]];
        let ca_f = cross(w, a1);
        let va1 = cross(v, a1);
        let wa2 = cross(w, a2);
        // τ − C_RB ν − C_A ν − D ν − g.
        let mut rhs = [0.0; 6];
        for k in 0..3 {
            let crb = m * wv[k] + m * wwg[k];
            let damp = c.d_lin[k].at(l) * nul[k] + c.d_quad[k].at(l) * nul[k].abs() * nul[k];
            rhs[k] = tau[k][l] - crb - ca_f[k] - damp + down[k] * net;
            let crb_t = m * g_wv[k] + w_iw[k];
            let j = k + 3;
            let damp_t = c.d_lin[j].at(l) * nul[j] + c.d_quad[j].at(l) * nul[j].abs() * nul[j];
            rhs[j] = tau[j][l] - crb_t - (va1[k] + wa2[k]) - damp_t + g_t[k];
        }
        for i in 0..6 {
            let row = &c.m_inv[i];
            d.nu[i][l] = row[0].at(l) * rhs[0]
                + row[1].at(l) * rhs[1]
                + row[2].at(l) * rhs[2]
                + row[3].at(l) * rhs[3]
                + row[4].at(l) * rhs[4]
                + row[5].at(l) * rhs[5];
        }
    }
    d
}

/// `x + k·h`, lane by lane.
#[inline(always)]
fn axpy<const N: usize, const K: usize>(
    x: &[[f64; N]; K],
    k: &[[f64; N]; K],
    h: f64,
) -> [[f64; N]; K] {
    let mut out = *x;
    for (o, kr) in out.iter_mut().zip(k) {
        for (a, b) in o.iter_mut().zip(kr) {
            *a += b * h;
        }
    }
    out
}

/// `x + (k1 + 2 k2 + 2 k3 + k4)·s`, lane by lane.
#[inline(always)]
fn combine<const N: usize, const K: usize>(x: &mut [[f64; N]; K], k: [&[[f64; N]; K]; 4], s: f64) {
    for r in 0..K {
        for l in 0..N {
            x[r][l] += (k[0][r][l] + (k[1][r][l] + k[2][r][l]) * 2.0 + k[3][r][l]) * s;
        }
    }
}

/// [`rk4`] for a swarm's group of [`LANES`] hulls, with the widest vectors this CPU has: on
/// x86-64 with AVX, the same code compiled for 256-bit registers (four hulls per instruction
/// instead of two). AVX adds no fused multiply-add here, and every lane operation is an IEEE
/// operation in either width, so the result is bit-identical to [`rk4`] on any x86-64.
///
/// The constants are those of one hull kind ([`DynConsts`]) or one set per lane
/// ([`LaneConsts`]); each lane's result is the same either way.
pub fn rk4_group<S: PerLane<LANES>>(c: &Consts<S>, x: &mut Lanes<LANES>, dt: f64) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        #[expect(
            unsafe_code,
            reason = "a target-feature function is called only after the CPU feature is detected"
        )]
        // SAFETY: `rk4_avx` requires AVX, which the running CPU has (detected just above).
        unsafe {
            rk4_avx(c, x, dt);
        }
        return;
    }
    rk4(c, x, dt);
}

/// [`rk4`] compiled for AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn rk4_avx<S: PerLane<LANES>>(c: &Consts<S>, x: &mut Lanes<LANES>, dt: f64) {
    rk4(c, x, dt);
}

/// Advances the `N` hulls of `x` by one classic RK4 step of `dt` \[s\] with their forces held
/// constant; the attitudes come out normalised.
#[inline(always)]
pub fn rk4<const N: usize, S: PerLane<N>>(c: &Consts<S>, x: &mut Lanes<N>, dt: f64) {
    let h = 0.5 * dt;
    let k1 = deriv(c, &x.p[2], &x.q, &x.nu, &x.tau);
    let p2 = axpy(&x.p, &k1.p, h);
    let k2 = deriv(
        c,
        &p2[2],
        &axpy(&x.q, &k1.q, h),
        &axpy(&x.nu, &k1.nu, h),
        &x.tau,
    );
    let p3 = axpy(&x.p, &k2.p, h);
    let k3 = deriv(
        c,
        &p3[2],
        &axpy(&x.q, &k2.q, h),
        &axpy(&x.nu, &k2.nu, h),
        &x.tau,
    );
    let p4 = axpy(&x.p, &k3.p, dt);
    let k4 = deriv(
        c,
        &p4[2],
        &axpy(&x.q, &k3.q, dt),
        &axpy(&x.nu, &k3.nu, dt),
        &x.tau,
    );
    let s = dt / 6.0;
    combine(&mut x.p, [&k1.p, &k2.p, &k3.p, &k4.p], s);
    combine(&mut x.q, [&k1.q, &k2.q, &k3.q, &k4.q], s);
    combine(&mut x.nu, [&k1.nu, &k2.nu, &k3.nu, &k4.nu], s);
    for l in 0..N {
        let n = (x.q[0][l] * x.q[0][l]
            + x.q[1][l] * x.q[1][l]
            + x.q[2][l] * x.q[2][l]
            + x.q[3][l] * x.q[3][l])
            .sqrt();
        for r in &mut x.q {
            r[l] /= n;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::presets;
    use crate::rigid_body::acceleration;

    fn setup() -> (BodyParams, MassProperties, Environment) {
        let v = presets::uauv2();
        let env = Environment {
            current: Vec3::new(0.05, -0.02, 0.01),
            ..Default::default()
        };
        let mp = v.mass_properties(v.initial_ballast(), env.density);
        (v.body, mp, env)
    }

    fn states() -> Vec<(RigidState, Vec6)> {
        (0..7)
            .map(|i| {
                let f = i as f64;
                let att = Quat::from_euler_angles(0.1 * f, -0.2 + 0.05 * f, 0.3 * f);
                let mut s = RigidState::at_rest(Vec3::new(f, -f, 0.02 * f), att);
                s.nu = Vec6::new(0.1 * f, -0.05, 0.02 * f, 0.3 - 0.1 * f, 0.2, -0.4 + 0.1 * f);
                (s, Vec6::new(0.05, -0.01 * f, 0.02, 1e-3, -2e-3 * f, 3e-3))
            })
            .collect()
    }

    /// The kernel's ν̇ at a state equals the reference [`acceleration`] built from the
    /// rigid-body module's matrices (Coriolis, damping, restoring including a hull breaking
    /// the surface), and ṗ, q̇ are the kinematics.
    #[test]
    fn derivative_matches_the_rigid_body_model() {
        let (body, mp, env) = setup();
        let c = DynConsts::new(&body, &mp, &env);
        for (s, tau) in states() {
            let mut x = Lanes::<1>::default();
            x.load(0, &s, &tau);
            let d = deriv(&c, &x.p[2], &x.q, &x.nu, &x.tau);
            let reference = acceleration(&body, &mp, &env, &s.position, &s.attitude, &s.nu, &tau);
            for k in 0..6 {
                let tol = 1e-12 * (1.0 + reference[k].abs());
                assert!(
                    (d.nu[k][0] - reference[k]).abs() < tol,
                    "ν̇[{k}] at depth {}: {} vs {}",
                    s.position.z,
                    d.nu[k][0],
                    reference[k]
                );
            }
            let pdot = s.attitude * s.nu.fixed_rows::<3>(0) + env.current;
            for k in 0..3 {
                assert!((d.p[k][0] - pdot[k]).abs() < 1e-14);
            }
            let w = s.nu.fixed_rows::<3>(3).into_owned();
            let qdot = s.attitude.quaternion() * Quaternion::from_parts(0.0, w) * 0.5;
            for (k, e) in [qdot.w, qdot.i, qdot.j, qdot.k].iter().enumerate() {
                assert!((d.q[k][0] - e).abs() < 1e-14);
            }
        }
    }

    /// A hull integrated alone and in any lane of a group of four (with the widest vectors of
    /// this CPU) comes out bit-identical, with constants shared by the group or its own.
    #[test]
    fn lanes_are_independent_and_bit_identical_to_one_hull() {
        let (body, mp, env) = setup();
        let c = DynConsts::new(&body, &mp, &env);
        let st = states();
        let mut alone = Vec::new();
        for (s, tau) in &st {
            let mut x = Lanes::<1>::default();
            x.load(0, s, tau);
            for _ in 0..50 {
                rk4(&c, &mut x, 0.01);
            }
            let mut out = s.clone();
            x.store(0, &mut out);
            alone.push(out);
        }
        for start in 0..st.len() - LANES + 1 {
            let mut x = Lanes::<LANES>::default();
            for l in 0..LANES {
                x.load(l, &st[start + l].0, &st[start + l].1);
            }
            for _ in 0..50 {
                rk4_group(&c, &mut x, 0.01);
            }
            for l in 0..LANES {
                let mut out = st[start + l].0.clone();
                x.store(l, &mut out);
                assert_eq!(out, alone[start + l], "lane {l} of group at {start}");
            }
        }
        // Each lane with constants of its own (another water current, mass, damping, added
        // mass) comes out as that hull integrated alone with its constants.
        let consts: Vec<DynConsts> = (0..LANES)
            .map(|l| {
                let f = l as f64;
                let mut b = body.clone();
                b.damping_linear *= 1.0 + 0.3 * f;
                b.damping_quadratic[2] *= 1.0 - 0.2 * f;
                b.added_mass[(0, 0)] *= 1.0 + 0.1 * f;
                b.added_mass[(5, 5)] *= 1.0 + 0.25 * f;
                let mp = MassProperties::new(&b, 1e-5 * f, &Vec3::new(0.01, 0.0, 0.0), env.density);
                let e = Environment {
                    current: Vec3::new(0.05 * f, -0.02, 0.01 * f),
                    ..env
                };
                DynConsts::new(&b, &mp, &e)
            })
            .collect();
        let mut per_lane = LaneConsts::<LANES>::splat(&c);
        for (l, cl) in consts.iter().enumerate() {
            per_lane.set(l, cl);
        }
        let mut x = Lanes::<LANES>::default();
        for (l, (s, tau)) in st.iter().take(LANES).enumerate() {
            x.load(l, s, tau);
        }
        for _ in 0..50 {
            rk4_group(&per_lane, &mut x, 0.01);
        }
        for (l, cl) in consts.iter().enumerate() {
            let mut one = Lanes::<1>::default();
            one.load(0, &st[l].0, &st[l].1);
            for _ in 0..50 {
                rk4(cl, &mut one, 0.01);
            }
            let (mut a, mut b) = (st[l].0.clone(), st[l].0.clone());
            x.store(l, &mut a);
            one.store(0, &mut b);
            assert_eq!(a, b, "lane {l} with constants of its own");
            if l > 0 {
                assert_ne!(a, alone[l], "lane {l}: its constants make a difference");
            }
        }
        // The attitude stays a unit quaternion.
        for s in &alone {
            assert!((s.attitude.quaternion().norm() - 1.0).abs() < 1e-15);
        }
    }
}
