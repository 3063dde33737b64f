//! Rigid-body and hydrodynamic parameters of a hull and the generalised forces they produce:
//! mass matrix M = M_RB + M_A, Coriolis–centripetal C(ν) (rigid body and added mass), linear +
//! quadratic damping D(ν) and the restoring forces g(η) of weight and buoyancy; the state
//! they act on ([`RigidState`]: pose and velocity relative to the water); and the equation of
//! motion below solved for the acceleration ([`acceleration`]), which the integrators use.
//!
//! Equation of motion (Fossen 2011, eq. 6.1 and 8.1, relative-velocity form for a constant
//! irrotational current):
//!
//! ```text
//! M ν̇_r + C_RB(ν_r) ν_r + C_A(ν_r) ν_r + D(ν_r) ν_r + g(η) = τ
//! ```
//!
//! C_RB uses the linear-velocity-independent parametrisation (Fossen Property 8.1), which is what
//! makes the relative-velocity form exact for a constant current. Both C matrices are
//! skew-symmetric, so they do no work: `ν·C(ν)ν = 0` (tested in `tests/physics.rs`).

use crate::math::{GRAVITY, Mat3, Mat6, Quat, Vec3, Vec6, join6, skew, split6};

/// Hull parameters: rigid body, added mass, damping and the hull's outer size.
///
/// The body origin is a point fixed in the hull (for the μAUV² preset: the centre of buoyancy).
/// All positions are body-frame coordinates of that origin.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyParams {
    /// Dry mass of the vehicle without ballast water \[kg\].
    pub mass: f64,
    /// Dry rigid-body inertia about the dry centre of gravity, body axes [kg·m²].
    pub inertia_cg: Mat3,
    /// Dry centre of gravity, body frame \[m\].
    pub cog: Vec3,
    /// Centre of buoyancy, body frame \[m\].
    pub cob: Vec3,
    /// Displaced volume when fully submerged \[m³\].
    pub volume: f64,
    /// Added-mass matrix M_A (symmetric, positive semi-definite) [kg, kg·m, kg·m²].
    pub added_mass: Mat6,
    /// Linear damping coefficients (X_u, Y_v, Z_w [N·s/m]; K_p, M_q, N_r [N·m·s]), all ≥ 0:
    /// the damping force is `+d ν` on the left-hand side.
    pub damping_linear: Vec6,
    /// Quadratic damping coefficients (X_u|u|, Y_v|v|, Z_w|w| [N·s²/m²]; K_p|p|, M_q|q|, N_r|r|
    /// [N·m·s²]), all ≥ 0: the damping force is `+d |ν| ν` on the left-hand side.
    pub damping_quadratic: Vec6,
    /// Outer hull extents along body x, y, z (length, width, height) \[m\]; used for collisions
    /// and for the buoyancy lost when the hull breaks the surface.
    pub hull_size: Vec3,
}

/// The water around the vehicle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Environment {
    /// Water density [kg/m³].
    pub density: f64,
    /// Gravitational acceleration [m/s²].
    pub gravity: f64,
    /// Constant, irrotational water current in the world (NED) frame [m/s].
    pub current: Vec3,
}

impl Default for Environment {
    fn default() -> Self {
        Self {
            density: 1000.0,
            gravity: GRAVITY,
            current: Vec3::zeros(),
        }
    }
}

/// Mass properties of the vehicle in its current ballast state (dry hull + ballast water).
///
/// Cached per vehicle and recomputed only when the ballast volume changes.
#[derive(Clone, Debug, PartialEq)]
pub struct MassProperties {
    /// Total mass \[kg\].
    pub mass: f64,
    /// Total centre of gravity, body frame \[m\].
    pub cog: Vec3,
    /// Total rigid-body inertia about the body origin [kg·m²].
    pub inertia_origin: Mat3,
    /// M = M_RB + M_A [kg, kg·m, kg·m²].
    pub m_total: Mat6,
    /// M⁻¹.
    pub m_inv: Mat6,
    /// Ballast water volume this cache was computed for \[m³\].
    pub ballast_volume: f64,
}

/// Inertia of a point mass `m` [kg] at `r` [m] about the origin [kg·m²].
fn point_inertia(m: f64, r: &Vec3) -> Mat3 {
    m * (Mat3::identity() * r.norm_squared() - r * r.transpose())
}

impl MassProperties {
    /// Mass properties of `body` carrying `ballast_volume` \[m³\] of water of density
    /// `density` [kg/m³] as a point mass at `ballast_position` \[m\].
    pub fn new(
        body: &BodyParams,
        ballast_volume: f64,
        ballast_position: &Vec3,
        density: f64,
    ) -> Self {
        let m_w = ballast_volume * density;
        let mass = body.mass + m_w;
        let cog = (body.cog * body.mass + ballast_position * m_w) / mass;
        let inertia_origin = body.inertia_cg
            + point_inertia(body.mass, &body.cog)
            + point_inertia(m_w, ballast_position);
        let mut m_rb = Mat6::zeros();
        m_rb.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(Mat3::identity() * mass));
        let s = skew(&cog) * mass;
        m_rb.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-s));
        m_rb.fixed_view_mut::<3, 3>(3, 0).copy_from(&s);
        m_rb.fixed_view_mut::<3, 3>(3, 3).copy_from(&inertia_origin);
        let m_total = m_rb + body.added_mass;
        let m_inv = m_total
            .cholesky()
            .map(|c| c.inverse())
            .or_else(|| m_total.try_inverse())
            .unwrap_or_else(Mat6::identity);
        Self {
            mass,
            cog,
            inertia_origin,
            m_total,
            m_inv,
            ballast_volume,
        }
    }

    /// Rigid-body Coriolis–centripetal force C_RB(ν)ν (linear-velocity-independent form).
    pub fn coriolis_rb(&self, nu: &Vec6) -> Vec6 {
        let (v, w) = split6(nu);
        let m = self.mass;
        let f = m * w.cross(&v) + m * w.cross(&w.cross(&self.cog));
        let iw = self.inertia_origin * w;
        let t = m * self.cog.cross(&w.cross(&v)) + w.cross(&iw);
        join6(&f, &t)
    }

    /// Kinetic energy ½ νᵀ M ν \[J\] (rigid body + added mass).
    pub fn kinetic_energy(&self, nu: &Vec6) -> f64 {
        0.5 * nu.dot(&(self.m_total * nu))
    }
}

impl BodyParams {
    /// Added-mass Coriolis–centripetal force C_A(ν)ν for a symmetric M_A.
    pub fn coriolis_added(&self, nu: &Vec6) -> Vec6 {
        let (v, w) = split6(nu);
        let a = self.added_mass * nu;
        let (a1, a2) = split6(&a);
        let f = w.cross(&a1);
        let t = v.cross(&a1) + w.cross(&a2);
        join6(&f, &t)
    }

    /// Damping force D(ν)ν = d_lin∘ν + d_quad∘|ν|∘ν.
    #[inline]
    pub fn damping(&self, nu: &Vec6) -> Vec6 {
        self.damping_linear.component_mul(nu)
            + self
                .damping_quadratic
                .component_mul(&nu.abs())
                .component_mul(nu)
    }

    /// Fraction of the hull volume below the surface (0…1) for a centre-of-buoyancy depth
    /// `depth_cob` \[m\]; the hull is treated as a vertical prism of height `hull_size.z`.
    #[inline]
    pub fn submerged_fraction(&self, depth_cob: f64) -> f64 {
        let h = self.hull_size.z.max(1e-6);
        ((depth_cob + 0.5 * h) / h).clamp(0.0, 1.0)
    }

    /// Restoring force g(η) (left-hand side) for attitude `att`, body-origin depth `depth` \[m\]
    /// and the current mass properties.
    pub fn restoring(
        &self,
        mp: &MassProperties,
        env: &Environment,
        depth: f64,
        att: &Quat,
    ) -> Vec6 {
        let down_body = att.inverse_transform_vector(&Vec3::z());
        let depth_cob = depth + att.transform_vector(&self.cob).z;
        let weight = mp.mass * env.gravity;
        let buoyancy = env.density * env.gravity * self.volume * self.submerged_fraction(depth_cob);
        let f_g = down_body * weight;
        let f_b = -down_body * buoyancy;
        let f = f_g + f_b;
        let t = mp.cog.cross(&f_g) + self.cob.cross(&f_b);
        -join6(&f, &t)
    }

    /// Potential energy of weight and buoyancy \[J\] for a fully submerged hull (zero at depth 0).
    pub fn potential_energy(
        &self,
        mp: &MassProperties,
        env: &Environment,
        depth: f64,
        att: &Quat,
    ) -> f64 {
        let z_g = depth + att.transform_vector(&mp.cog).z;
        let z_b = depth + att.transform_vector(&self.cob).z;
        -mp.mass * env.gravity * z_g + env.density * env.gravity * self.volume * z_b
    }
}

/// Position, attitude and velocity of one hull.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidState {
    /// Position of the body origin in the world (NED) frame \[m\]; `z` is depth.
    pub position: Vec3,
    /// Attitude (body → world).
    pub attitude: Quat,
    /// Velocity relative to the water, body frame: (u, v, w) [m/s], (p, q, r) [rad/s].
    pub nu: Vec6,
}

impl RigidState {
    /// Whether every component (position, attitude, velocities) is a finite number.
    pub fn is_finite(&self) -> bool {
        self.position.iter().all(|x| x.is_finite())
            && self.attitude.coords.iter().all(|x| x.is_finite())
            && self.nu.iter().all(|x| x.is_finite())
    }

    /// At rest at `position` \[m\] with attitude `attitude`.
    pub fn at_rest(position: Vec3, attitude: Quat) -> Self {
        Self {
            position,
            attitude,
            nu: Vec6::zeros(),
        }
    }

    /// Velocity over ground in the world frame [m/s].
    pub fn world_velocity(&self, env: &Environment) -> Vec3 {
        let (v, _) = split6(&self.nu);
        self.attitude * v + env.current
    }
}

/// Body acceleration ν̇_r [m/s², rad/s²] for the given state and applied force τ: the equation
/// of motion above solved for ν̇_r, M⁻¹ (τ − C_RB(ν_r) ν_r − C_A(ν_r) ν_r − D(ν_r) ν_r − g(η)).
#[inline]
pub fn acceleration(
    body: &BodyParams,
    mp: &MassProperties,
    env: &Environment,
    position: &Vec3,
    attitude: &Quat,
    nu: &Vec6,
    tau: &Vec6,
) -> Vec6 {
    let rhs = tau
        - mp.coriolis_rb(nu)
        - body.coriolis_added(nu)
        - body.damping(nu)
        - body.restoring(mp, env, position.z, attitude);
    mp.m_inv * rhs
}
