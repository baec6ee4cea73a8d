//! File formats: recordings in (CSV of ADC codes for `replay`, named columns for `allan` and
//! `drift`), SVG charts out.

pub mod columns;
pub mod plot;
pub mod recording;
