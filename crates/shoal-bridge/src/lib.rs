//! # shoal-bridge
//!
//! External swarm agents for shoal over shared memory ([iceoryx2](https://docs.rs/iceoryx2)),
//! the only crate of the workspace that knows iceoryx2:
//! - [`protocol`]: the versioned wire format (`#[repr(C)]` observation and command slices);
//! - [`convert`]: those wire structs to and from the world's commands and observations;
//! - [`host`]: the world side — services per agent, lock-step and free-running exchange,
//!   timeouts, dead-agent detection, fallback, command validation, clean shutdown;
//! - [`agent`]: the agent side — attach to a world, receive observations, answer commands.

pub mod agent;
pub mod convert;
pub mod host;
pub mod protocol;

/// A problem of the bridge (setting up services, talking to the other side).
#[derive(Debug, thiserror::Error)]
pub enum BridgeError {
    /// An iceoryx2 call failed.
    #[error("shared memory (iceoryx2): {op}: {detail}")]
    Ipc {
        /// What the bridge was doing.
        op: IpcOp,
        /// iceoryx2's error (and the agent, where one is concerned), as text: only this crate
        /// knows iceoryx2's types.
        detail: String,
    },
    /// Another world already uses this prefix.
    #[error(
        "prefix `{0}` is in use by another running world (or an agent of a world that died is still attached); choose another `[agents] prefix` or `--prefix`"
    )]
    PrefixInUse(String),
    /// The world did not appear in time.
    #[error("no world with prefix `{prefix}` and agent `{agent}` appeared within {secs} s")]
    NoWorld {
        /// Prefix.
        prefix: String,
        /// Agent name.
        agent: String,
        /// Waited \[s\].
        secs: f64,
    },
    /// Another process is already attached as this agent.
    #[error("agent `{0}` is already attached to this world (one process per agent name)")]
    AgentTaken(String),
    /// The agent process was asked to end (Ctrl-C or SIGTERM).
    #[error("interrupted (Ctrl-C or SIGTERM)")]
    Interrupted,
}

/// The iceoryx2 operation behind a [`BridgeError::Ipc`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum IpcOp {
    /// Naming the process's node.
    #[error("node name")]
    NodeName,
    /// Creating the node.
    #[error("node")]
    Node,
    /// Naming a service.
    #[error("service name")]
    ServiceName,
    /// Creating or opening an agent's services.
    #[error("creating the services")]
    Services,
    /// Creating the observation publisher.
    #[error("observation publisher")]
    ObservationPublisher,
    /// Creating the command subscriber.
    #[error("command subscriber")]
    CommandSubscriber,
    /// Receiving observations.
    #[error("receiving observations")]
    ReceiveObservations,
    /// Loaning a command slice to write.
    #[error("loaning a command slice")]
    Loan,
    /// Sending commands.
    #[error("sending commands")]
    SendCommands,
    /// Publishing observations.
    #[error("publishing observations")]
    PublishObservations,
}

/// Name of an agent's service `leaf` (`obs` or `cmd`) in the world with `prefix`.
pub fn service_name(prefix: &str, agent: &str, leaf: &str) -> String {
    format!("shoal/{prefix}/{agent}/{leaf}")
}

pub(crate) fn ipc<E: std::fmt::Debug>(op: IpcOp) -> impl FnOnce(E) -> BridgeError {
    move |e| BridgeError::Ipc {
        op,
        detail: format!("{e:?}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_iceoryx2_failure_names_the_operation_a_caller_can_match() {
        let e = ipc(IpcOp::PublishObservations)("ConnectionBroken");
        assert!(matches!(
            &e,
            BridgeError::Ipc { op: IpcOp::PublishObservations, detail } if detail == "\"ConnectionBroken\""
        ));
        assert_eq!(
            e.to_string(),
            "shared memory (iceoryx2): publishing observations: \"ConnectionBroken\""
        );
    }
}
