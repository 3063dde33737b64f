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

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_model::math::Vec3;
    use shoal_model::optics::ModemPose;

    /// A transmission of vehicle `tx`'s modem `modem` starting at `start` \[s\].
    fn tx(start: f64, tx: u32, modem: usize) -> Transmission {
        let pose = ModemPose {
            position: Vec3::zeros(),
            axis: Vec3::x(),
        };
        Transmission {
            tx,
            start,
            end: start + 0.01,
            ..Transmission::sent_from(0, modem, pose)
        }
    }

    /// Parts merge into the order one walk starts them in — by start, then sender — and a
    /// sender's transmissions at one instant keep their part's order (its ports in the order
    /// its turns sent them, here 2 before 0), whatever the order of the parts (seen failing
    /// with the parts concatenated).
    #[test]
    fn parts_merge_by_start_then_sender_keeping_each_parts_order() {
        let a = || Started {
            txs: vec![tx(0.1, 3, 2), tx(0.1, 3, 0), tx(0.3, 1, 0)],
        };
        let b = || Started {
            txs: vec![tx(0.1, 2, 1), tx(0.2, 7, 0), tx(0.3, 5, 3)],
        };
        let want = [
            (0.1, 2, 1),
            (0.1, 3, 2),
            (0.1, 3, 0),
            (0.2, 7, 0),
            (0.3, 1, 0),
            (0.3, 5, 3),
        ];
        for parts in [
            vec![a(), b()],
            vec![b(), a()],
            vec![Started::default(), b(), a()],
        ] {
            let got: Vec<_> = Started::merge(parts)
                .txs
                .iter()
                .map(|x| (x.start, x.tx, x.modem))
                .collect();
            assert_eq!(got, want);
        }
    }
}
