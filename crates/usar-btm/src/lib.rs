//! `usar-btm`: Behavioral Trace Maps (paper 004). The node and link tables ([`model`]), their
//! SQLite database written while a robot drives ([`store`]), and JSON / GraphML exchange
//! ([`exchange`]). Generation from laser scans, locomotion, planning and merging build on these.

pub mod exchange;
pub mod merge;
pub mod model;
pub mod plan;
pub mod render;
pub mod store;

pub use self::model::{Btm, Link, Node};
pub use self::store::{BtmError, BtmStore};
