//! # shoal-bridge
//!
//! External swarm agents for shoal over shared memory ([iceoryx2](https://docs.rs/iceoryx2)),
//! the only crate of the workspace that knows iceoryx2:
//! - [`protocol`]: the versioned wire format (`#[repr(C)]` observation and command slices);
//! - [`host`]: the world side — services per agent, lock-step and free-running exchange,
//!   timeouts, dead-agent detection, fallback, command validation, clean shutdown;
//! - [`agent`]: the agent side — attach to a world, receive observations, answer commands.

pub mod agent;
pub mod host;
pub mod protocol;

/// A problem of the bridge (setting up services, talking to the other side).
#[derive(Debug, thiserror::Error)]
pub enum BridgeError {
    /// An iceoryx2 call failed.
    #[error("shared memory (iceoryx2): {0}")]
    Ipc(String),
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

/// Name of an agent's service `leaf` (`obs` or `cmd`) in the world with `prefix`.
pub fn service_name(prefix: &str, agent: &str, leaf: &str) -> String {
    format!("shoal/{prefix}/{agent}/{leaf}")
}

pub(crate) fn ipc<E: std::fmt::Debug>(what: &str) -> impl FnOnce(E) -> BridgeError + '_ {
    move |e| BridgeError::Ipc(format!("{what}: {e:?}"))
}
