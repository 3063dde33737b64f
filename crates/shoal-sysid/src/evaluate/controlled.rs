//! A dataset replayed with its controller: each run that carries its controller's references
//! gets a closed-loop twin beside its replay ([`crate::evaluate::open_loop::control`]): the
//! same model with the vehicle's controller in the loop following the logged references,
//! never re-anchored (a simulation of the mission as DIDIM makes it). The thruster commands the run logged become
//! compared channels of their own ([`ChannelKind::Command`]), each with the resolution and
//! noise weight read from its own samples, predicted by the twin; the logged commands still
//! drive the replay itself, whose states are compared as before.
//!
//! So one fit sees both views of a log under feedback: the response from command to state
//! (re-anchored, where a thruster's lag or a hull's damping shows its shape) and what the
//! controller compensates (a thrust lost, answered by larger commands while the states stay
//! on their setpoints).

use crate::evaluate::dataset::Dataset;
use crate::evaluate::open_loop::control::ReplayControl;
use crate::log::run::{Channel, ChannelKind};
use shoal_model::vehicle::VehicleModel;
use std::sync::Arc;

impl Dataset {
    /// Gives every run a closed-loop twin with the controller of `baseline` (the vehicle as
    /// given) and compares the logged thruster commands with the twin's; the command channels
    /// added, or why not (then the dataset is left as it was): a run without references, a vehicle without
    /// a built-in controller, or no logged thruster command to compare.
    pub fn close_loop(&mut self, baseline: &VehicleModel) -> Result<Vec<ChannelKind>, String> {
        self.open_loop();
        let mut controls = Vec::with_capacity(self.runs.len());
        for rd in &self.runs {
            let ctl = ReplayControl::new(baseline, &rd.run)
                .map_err(|why| format!("run `{}`: {why}", rd.run.name))?;
            if ctl.command_channels(&rd.run).is_empty() {
                return Err(format!(
                    "run `{}` logs no thruster command (u.<thruster>) to compare",
                    rd.run.name
                ));
            }
            controls.push(ctl);
        }
        let mut added: Vec<ChannelKind> = Vec::new();
        for (rd, ctl) in self.runs.iter_mut().zip(controls) {
            for kind in ctl.command_channels(&rd.run) {
                let input = rd.run.input(kind.name()).expect("a logged command");
                let channel = Channel {
                    kind,
                    column: input.column,
                    rows: (0..rd.run.t.len()).collect(),
                    values: input.values.clone(),
                };
                rd.channels.push(rd.run.channels.len());
                rd.run.channels.push(channel);
                if !added.contains(&kind) {
                    added.push(kind);
                }
            }
            rd.init.control = Some(Arc::new(ctl));
        }
        self.replan();
        Ok(added)
    }

    /// Replays every run without a twin again (undoes [`Dataset::close_loop`]).
    pub(crate) fn open_loop(&mut self) {
        let mut changed = false;
        for rd in &mut self.runs {
            changed |= rd.init.control.take().is_some();
            let keep = rd
                .run
                .channels
                .iter()
                .position(|c| c.kind.is_command())
                .unwrap_or(rd.run.channels.len());
            rd.run.channels.truncate(keep);
            rd.channels.retain(|&i| i < keep);
        }
        if changed {
            self.replan();
        }
    }
}
