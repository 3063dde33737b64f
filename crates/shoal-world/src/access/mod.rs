//! A modem's link layer as a world states it: how it gets the medium (the world file's
//! `access`: [`Access`]) and how it retries unicast frames sent with acknowledgement
//! ([`LinkParams`]). The protocols that act on them are the simulation's
//! (`shoal_sim::comm::mac`, one file each); this is what a world says about them, checked on
//! load.
//!
//! In a world file a modem's `access` is a protocol's name with its defaults
//! (`access = "tdma"`) or a table naming it with its settings
//! (`access = { kind = "csma_ca", cw_min = 32 }`); a setting of another protocol is an unknown
//! field. Each protocol with settings has its file here: the settings (SI, or in a field named
//! for its unit), their defaults, the allowed range of each ([`ranges`]) and the numbers its
//! checks need ([`Protocol::numbers`]). Adding a protocol is its file and one line in
//! [`protocols!`]'s list below (and, in the simulation, its [`Access`] variant's protocol).

mod carrier_sense;
mod csma_ca;
mod p_persistent;
mod slotted_aloha;
mod tdma;

use crate::range::{End, FieldRange, r};
use serde::{Deserialize, Deserializer, Serialize};

pub use carrier_sense::CarrierSense;
pub use csma_ca::CsmaCa;
pub use p_persistent::PPersistent;
pub use slotted_aloha::SlottedAloha;
pub use tdma::Tdma;

/// The link layer of one modem.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkParams {
    /// Medium access.
    pub access: Access,
    /// Retransmissions of an unacknowledged unicast frame before the sender gives up.
    pub retries: u32,
    /// How long a sender waits for an acknowledgement after its frame ended \[s\].
    pub ack_timeout: f64,
}

/// Unslotted ALOHA, which has no settings (a table naming it with any is refused).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Aloha {}

impl Default for Access {
    fn default() -> Self {
        Access::Aloha(Aloha {})
    }
}

/// What the checks of a protocol's settings may depend on: the modem's frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frames {
    /// Airtime of the modem's longest frame (a `max_payload` one) \[s\].
    pub longest: f64,
}

/// One number of a protocol's settings to check against its range: the field's name in the
/// `access` table, its value, and the values of the range's ends given by other numbers
/// ([`End::Field`]; `None` where the end is fixed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Number {
    /// Field name in the `access` table.
    pub name: &'static str,
    /// Its value, in the field's unit.
    pub value: f64,
    /// Value of a lower end given by another number.
    pub lo: Option<f64>,
    /// Value of an upper end given by another number.
    pub hi: Option<f64>,
}

impl Number {
    /// A number whose range has fixed ends.
    pub fn new(name: &'static str, value: f64) -> Self {
        Self {
            name,
            value,
            lo: None,
            hi: None,
        }
    }
}

/// What every protocol's settings tell the loader and the medium.
pub trait Protocol {
    /// The numbers to check, each against its row of the protocol's ranges.
    fn numbers(&self, frames: &Frames) -> Vec<Number>;
    /// The slot length of slotted protocols \[s\] (`None` for unslotted ones).
    fn slot(&self) -> Option<f64> {
        None
    }
    /// Largest relative rate error of a vehicle's clock that the protocol allows \[1\].
    fn clock_drift(&self) -> f64 {
        0.0
    }
}

/// The busy threshold of the protocols that sense the carrier (one row for all of them).
pub(crate) const THRESHOLD: FieldRange = r(
    "vehicles[].model.modems[].access.threshold",
    End::Closed(1e-18),
    End::Closed(1.0),
    "W",
    "carrier_sense, csma_ca, p_persistent: busy threshold on received optical power",
);

/// The slot of the protocols whose frames start on slot boundaries (one row for all of them).
pub(crate) const SLOT: FieldRange = r(
    "vehicles[].model.modems[].access.slot",
    End::Field("the airtime of a max_payload frame"),
    End::Closed(100.0),
    "s",
    "slotted_aloha, tdma: a slot holds the longest frame",
);

/// The contention slot of the protocols that count or draw slots while the channel is idle
/// (one row for all of them).
pub(crate) const BACKOFF_SLOT: FieldRange = r(
    "vehicles[].model.modems[].access.backoff_slot",
    End::Closed(1e-6),
    End::Closed(1.0),
    "s",
    "csma_ca, p_persistent: contention slot (at least the time to sense the carrier)",
);

/// Declares the protocols with settings: `Variant(Type) in module, "name"`. Generates
/// [`Access`] (unslotted ALOHA and one variant each), its dispatch to [`Protocol`] and
/// [`ranges`].
macro_rules! protocols {
    ($( $(#[$doc:meta])* $variant:ident in $module:ident ),* $(,)?) => {
        /// A modem's medium access, as the world file states it (see the module doc).
        #[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
        #[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
        pub enum Access {
            /// Unslotted ALOHA: transmit as soon as a frame is ready and the modem is idle.
            Aloha(Aloha),
            $( $(#[$doc])* $variant($variant), )*
        }

        impl Access {
            /// The protocol's settings (`None` for unslotted ALOHA, which has none).
            pub fn protocol(&self) -> Option<&dyn Protocol> {
                match self {
                    Access::Aloha(_) => None,
                    $( Access::$variant(p) => Some(p), )*
                }
            }
        }

        /// The allowed ranges of every protocol's settings (a row shared by several
        /// protocols comes once).
        pub fn ranges() -> Vec<&'static FieldRange> {
            let mut out: Vec<&'static FieldRange> = Vec::new();
            for r in [$( $module::RANGES, )*].into_iter().flatten() {
                // A shared row (the same constant) once; two different rows for one field
                // both stay, and the ranges table's uniqueness test names the field.
                if !out.iter().any(|o| *o == r) {
                    out.push(r);
                }
            }
            out
        }
    };
}

protocols! {
    /// Listen before talk with a random back-off.
    CarrierSense in carrier_sense,
    /// Slotted ALOHA on the vehicle's own clock.
    SlottedAloha in slotted_aloha,
    /// Time-division from a fixed schedule.
    Tdma in tdma,
    /// CSMA/CA with binary exponential back-off.
    CsmaCa in csma_ca,
    /// Slotted p-persistent CSMA.
    PPersistent in p_persistent,
}

impl Access {
    /// The slot length of slotted protocols \[s\] (`None` for unslotted ones).
    pub fn slot(&self) -> Option<f64> {
        self.protocol().and_then(|p| p.slot())
    }

    /// Largest relative rate error of a vehicle's clock \[1\] (0: exact clocks).
    pub fn clock_drift(&self) -> f64 {
        self.protocol().map_or(0.0, |p| p.clock_drift())
    }

    /// The numbers of its settings to check (none for ALOHA).
    pub fn numbers(&self, frames: &Frames) -> Vec<Number> {
        self.protocol().map_or_else(Vec::new, |p| p.numbers(frames))
    }

    /// Reads a modem's `access` as a world file writes it: a protocol's name (its settings
    /// at their defaults) or a table naming it (`kind`) with its settings.
    pub fn from_file<'de, D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(FileVisitor)
    }
}

/// The two forms of `access` in a world file (see [`Access::from_file`]).
struct FileVisitor;

impl<'de> serde::de::Visitor<'de> for FileVisitor {
    type Value = Access;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("a protocol's name, or a table with its `kind` and settings")
    }

    fn visit_str<E: serde::de::Error>(self, name: &str) -> Result<Access, E> {
        let table = std::iter::once(("kind", name));
        Access::deserialize(serde::de::value::MapDeserializer::<_, E>::new(table))
    }

    fn visit_map<M: serde::de::MapAccess<'de>>(self, map: M) -> Result<Access, M::Error> {
        Access::deserialize(serde::de::value::MapAccessDeserializer::new(map))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(toml_text: &str) -> Result<Access, String> {
        #[derive(Deserialize)]
        struct Modem {
            #[serde(deserialize_with = "Access::from_file")]
            access: Access,
        }
        toml::from_str::<Modem>(toml_text)
            .map(|m| m.access)
            .map_err(|e| e.to_string())
    }

    /// A name gives the protocol's defaults; a table overrides some; a setting of another
    /// protocol, or an unknown protocol, is refused.
    #[test]
    fn access_is_a_name_or_a_table() {
        assert_eq!(read("access = \"aloha\""), Ok(Access::default()));
        assert_eq!(
            read("access = \"csma_ca\""),
            Ok(Access::CsmaCa(CsmaCa::default()))
        );
        assert_eq!(
            read("access = { kind = \"csma_ca\", cw_min = 32 }"),
            Ok(Access::CsmaCa(CsmaCa {
                cw_min: 32,
                ..CsmaCa::default()
            }))
        );
        let e = read("access = { kind = \"tdma\", cw_min = 32 }").unwrap_err();
        assert!(e.contains("unknown field `cw_min`"), "{e}");
        let e = read("access = \"token_ring\"").unwrap_err();
        assert!(e.contains("unknown variant `token_ring`"), "{e}");
        let e = read("access = { kind = \"aloha\", slot = 0.1 }").unwrap_err();
        assert!(e.contains("unknown field `slot`"), "{e}");
    }

    /// Rows for the same field are one definition (listed once): no two protocols give one
    /// field different ranges.
    #[test]
    fn every_range_is_listed_once() {
        let rows = ranges();
        for (i, a) in rows.iter().enumerate() {
            assert!(
                rows[i + 1..].iter().all(|b| b.field != a.field),
                "{}",
                a.field
            );
        }
        assert!(rows.iter().any(|r| r.field == THRESHOLD.field));
    }
}
