//! The fuzz harness in CI: every loader for `USAR_FUZZ_SECONDS` seconds (default 15), and the
//! inputs it once found, as named regression tests.

#[global_allocator]
static METER: usar_fuzz::meter::MeteredAllocator = usar_fuzz::meter::MeteredAllocator;

mod loaders;
mod regressions;
