//! The link between the two nodes (issue #29): the messages they exchange each control period
//! and their timing contract ([`messages`]).

pub mod messages;
