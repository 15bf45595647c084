//! The console's tests: message validation, the access token, floods of malformed messages,
//! many viewers, and the end-to-end test in a real headless Chromium.

mod browser;
mod common;
mod malformed;
mod protocol;
mod security;
mod viewers;
