//! What the transmit phase's walk started ([`Started`]): the transmissions, kept by the walk
//! while it goes on (it reads the medium only) and put on the medium's record when it is done
//! ([`Started::apply`]) — numbered, counted, their LED time added to their flows. A step
//! walked in independent parts ([`super::parts`]) gives one [`Started`] per part, merged into
//! the order the walk of the whole step starts them in ([`Started::merge`]).

use super::air::OnRecord;
use super::frames::Kind;
use super::medium::{Medium, Transmission};
use shoal_model::optics::ModemParams;

/// The transmissions a walk started, in the order it started them (on record after the
/// medium's list; numbered by [`Started::apply`]).
#[derive(Default)]
pub(super) struct Started {
    pub(super) txs: Vec<Transmission>,
}

/// The LED time \[s\] and optical energy \[J\] of a frame of `payload` bytes sent by a modem
/// with `params`.
pub(super) fn led_use(params: &ModemParams, payload: usize) -> (f64, f64) {
    let airtime = params.airtime(payload);
    (airtime, params.led.power * airtime)
}

/// The flow (sender, destination) a frame of kind `kind` sent by `vehicle` counts to: a
/// unicast's copies, and the acknowledgements of one, are its flow's; broadcasts none.
pub(super) fn flow_of(kind: &Kind, vehicle: u32) -> Option<(u32, u32)> {
    match *kind {
        Kind::Unicast { to, .. } => Some((vehicle, to)),
        Kind::Ack { to, .. } => Some((to, vehicle)),
        Kind::Broadcast => None,
    }
}

impl Started {
    /// The transmissions on record while the walk goes on: `m`'s, then these.
    pub(super) fn on_record<'a>(&'a self, m: &'a Medium) -> OnRecord<'a> {
        OnRecord {
            medium: &m.txs,
            started: &self.txs,
        }
    }

    /// Where the next transmission started will be in the list on record of `m`.
    pub(super) fn next_index(&self, m: &Medium) -> usize {
        m.txs.len() + self.txs.len()
    }

    /// The transmissions of independent parts of a step's walk as one walk of the step starts
    /// them: by start time, then sender (the walk's turns go in time order, ties by vehicle),
    /// each part's order kept among its own — a vehicle's transmissions are all in one part.
    pub(super) fn merge(parts: Vec<Started>) -> Started {
        let mut parts = parts.into_iter().filter(|p| !p.txs.is_empty());
        let Some(first) = parts.next() else {
            return Started::default();
        };
        parts.fold(first, |a, b| {
            let mut txs = Vec::with_capacity(a.txs.len() + b.txs.len());
            let (mut a, mut b) = (a.txs.into_iter().peekable(), b.txs.into_iter().peekable());
            while let (Some(x), Some(y)) = (a.peek(), b.peek()) {
                let b_first = y.start.total_cmp(&x.start).then(y.tx.cmp(&x.tx)).is_lt();
                txs.extend(if b_first { b.next() } else { a.next() });
            }
            txs.extend(a);
            txs.extend(b);
            Started { txs }
        })
    }

    /// Puts what the walk started on the medium's record, in order: numbered from the
    /// medium's next id, counted, and the LED time and energy of each unicast's copies and
    /// acknowledgements added to its flow.
    pub(super) fn apply(mut self, m: &mut Medium) {
        for x in &mut self.txs {
            x.id = m.next_id;
            m.next_id += 1;
            if let Some((from, to)) = flow_of(&x.kind, x.tx) {
                let params = &m.kinds[x.tx as usize].params.modems[x.modem];
                let (on, energy) = led_use(params, x.payload.len());
                let f = m.flows.get(from, to);
                f.led_on_s += on;
                f.led_energy_j += energy;
            }
        }
        m.started.0 += self.txs.len() as u64;
        m.started.1 += self.txs.iter().map(|x| x.bits).sum::<u64>();
        m.txs.extend(self.txs);
    }
}
