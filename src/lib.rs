//! shoal facade
