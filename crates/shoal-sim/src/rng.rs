//! The per-vehicle random streams: one world seed gives every vehicle its own independent
//! stream per purpose (sensor noise, the optical medium, behaviours), so results do not depend
//! on the order in which vehicles are visited or on the number of threads.

use rand::SeedableRng;

/// Random-stream purposes; each vehicle gets stream `id · 16 + purpose` of the world seed.
pub mod stream {
    /// Sensor noise.
    pub const SENSORS: u64 = 0;
    /// The optical medium (back-offs, reception draws).
    pub const COMM: u64 = 1;
    /// Built-in behaviours.
    pub const BEHAVIOUR: u64 = 2;
    /// The error of the vehicle's clock (drawn once, by slotted medium access).
    pub const CLOCK: u64 = 3;
}

/// The generator of every per-vehicle random stream: xoshiro256++ (rand's named, portable
/// generator: the same numbers on every platform and release), 32 bytes of state — a
/// ChaCha stream with its block buffer takes ten times that, 0.6 GB for the two streams of
/// a million vehicles.
pub type VehicleRng = rand::rngs::Xoshiro256PlusPlus;

/// The RNG of vehicle `id` for `purpose`, derived from the world seed only: its 256-bit
/// state is SplitMix64's expansion of the world seed mixed with the stream number
/// `id · 16 + purpose`, so streams of different vehicles, purposes and seeds start at
/// unrelated points of the 2²⁵⁶ − 1 period.
pub fn vehicle_rng(seed: u64, id: u32, purpose: u64) -> VehicleRng {
    let stream = u64::from(id) * 16 + purpose;
    VehicleRng::seed_from_u64(splitmix64(seed ^ splitmix64(stream)))
}

/// One SplitMix64 output for `x` (Steele, Lea & Flood 2014): a bijective 64-bit mixer.
fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}
