//! The test kit of the rosbag2 reader's tests and benchmark: bags whose truth is known
//! ([`bagkit`]), message bodies written byte by byte with their layout ([`cdr`]), and seeded
//! mutations of bodies, schema texts and files ([`mutate`]).

pub mod bagkit;
pub mod cdr;
pub mod mutate;
