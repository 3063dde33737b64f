//! Mass properties by ballast volume, kept across the replays of one dataset.
//!
//! While a vehicle pumps, its ballast changes every physics step and with it the mass
//! properties: mass, centre of gravity, inertia, and the inverse of the 6 × 6 mass matrix —
//! a Cholesky factorisation per step. A replay of a diving log pumps for long stretches, and
//! a search replays the same log thousands of times with the same pump commands, so the same
//! volumes come back replay after replay. This table computes the properties of a volume
//! once per vehicle body, water density and ballast position and hands out the same values
//! again (the numbers are those of [`VehicleParams::mass_properties`], bit for bit).

use shoal_model::rigid_body::MassProperties;
use shoal_model::vehicle::VehicleParams;
use std::collections::{HashMap, VecDeque};
use std::sync::{Arc, Mutex, MutexGuard};

/// Most bodies (different mass-relevant parameters) a table keeps.
const MAX_BODIES: usize = 8;

/// Most volumes kept per body (≈ 0.75 KB each); further volumes are computed and not kept.
const MAX_VOLUMES: usize = 100_000;

/// The mass properties of the volumes met so far, per body.
#[derive(Default)]
pub struct MassTable {
    bodies: Mutex<VecDeque<(Vec<u64>, Arc<Volumes>)>>,
}

impl std::fmt::Debug for MassTable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MassTable")
            .field("bodies", &lock(&self.bodies).len())
            .finish()
    }
}

/// One body's volumes: volume (bits) → properties.
type Volumes = Mutex<HashMap<u64, Arc<MassProperties>>>;

/// The properties of one vehicle body in water of one density, by ballast volume.
pub struct BodyMasses {
    params: VehicleParams,
    density: f64,
    volumes: Arc<Volumes>,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    // Every change is a single insert or push, so a panic elsewhere leaves the data whole.
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl MassTable {
    /// The volumes of `params`'s body (what its mass properties depend on: the hull's mass,
    /// centre of gravity, inertia and added mass, the tank's position) in water of `density`
    /// [kg/m³].
    pub fn body(&self, params: &VehicleParams, density: f64) -> BodyMasses {
        let b = &params.body;
        let tank = params.ballast.as_ref().map(|t| t.position);
        let key: Vec<u64> = std::iter::once(b.mass)
            .chain(b.cog.iter().copied())
            .chain(b.inertia_cg.iter().copied())
            .chain(b.added_mass.iter().copied())
            .chain(tank.iter().flat_map(|p| p.iter().copied()))
            .chain([density])
            .map(f64::to_bits)
            .collect();
        let mut bodies = lock(&self.bodies);
        let volumes = match bodies.iter().position(|(k, _)| *k == key) {
            Some(i) => {
                let hit = bodies.remove(i).expect("index from position");
                let v = hit.1.clone();
                bodies.push_back(hit);
                v
            }
            None => {
                let v = Arc::new(Volumes::default());
                bodies.push_back((key, v.clone()));
                if bodies.len() > MAX_BODIES {
                    bodies.pop_front();
                }
                v
            }
        };
        BodyMasses {
            params: params.clone(),
            density,
            volumes,
        }
    }
}

impl BodyMasses {
    /// The mass properties with `volume` \[m³\] of ballast water.
    pub fn at(&self, volume: f64) -> Arc<MassProperties> {
        let key = volume.to_bits();
        if let Some(m) = lock(&self.volumes).get(&key) {
            return m.clone();
        }
        let m = Arc::new(self.params.mass_properties(volume, self.density));
        let mut volumes = lock(&self.volumes);
        if volumes.len() < MAX_VOLUMES {
            volumes.insert(key, m.clone());
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kept_values_are_the_computed_ones_and_bodies_are_told_apart() {
        let table = MassTable::default();
        let p = shoal_model::presets::uauv2();
        let body = table.body(&p, 1000.0);
        for v in [0.0, 1e-6, 7.3e-6, 1e-6] {
            assert_eq!(*body.at(v), p.mass_properties(v, 1000.0));
        }
        // The same volume is one value while kept.
        assert!(Arc::ptr_eq(
            &body.at(1e-6),
            &table.body(&p, 1000.0).at(1e-6)
        ));
        // Another density, another hull mass, another tank position: other values.
        let denser = table.body(&p, 1025.0);
        assert_eq!(*denser.at(1e-6), p.mass_properties(1e-6, 1025.0));
        let mut heavy = p.clone();
        heavy.body.mass += 0.1;
        assert_eq!(
            *table.body(&heavy, 1000.0).at(1e-6),
            heavy.mass_properties(1e-6, 1000.0)
        );
        let mut moved = p.clone();
        moved.ballast.as_mut().unwrap().position.x += 0.01;
        assert_eq!(
            *table.body(&moved, 1000.0).at(1e-6),
            moved.mass_properties(1e-6, 1000.0)
        );
    }
}
