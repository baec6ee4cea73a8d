//! Benchmark material, apart from the product: the kernels `cargo lab speed` times in QEMU and
//! on the host ([`kernels`]), the alternative pipelines it weighs against the default
//! ([`variants`]), and the deterministic ADC trace both run on ([`testsignal`]).
//!
//! The device never uses this module; nothing of the product depends on it.

pub mod kernels;
pub mod testsignal;
pub mod variants;
