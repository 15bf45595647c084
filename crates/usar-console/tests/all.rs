//! The console's tests: message validation, the access token, origins and hosts, limits
//! (connections, message sizes, deadlines, token attempts, mission files), floods of malformed
//! messages, the live mission's robots, many viewers, and the end-to-end test in a real headless Chromium.

mod browser;
mod common;
mod limits;
mod malformed;
mod mission;
mod protocol;
mod security;
mod viewers;
