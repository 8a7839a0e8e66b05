//! Placeholder until the analytic module lands.
pub fn terzaghi_pressure(_z: f64, _t: f64, _h: f64, _p: f64, _c: f64) -> f64 { f64::NAN }
pub fn terzaghi_settlement(_t: f64, _h: f64, _p: f64, _c: f64, _m: f64) -> f64 { f64::NAN }
pub fn cryer_center_pressure(_t: f64, _a: f64, _nu: f64, _c: f64) -> f64 { f64::NAN }
