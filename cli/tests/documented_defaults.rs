//! The application's defaults stated in the docs are the ones in the code
//! (the library's: `tests/documented_defaults.rs`).

#[test]
fn the_record_tolerance_is_the_documented_one() {
    // regression.rs: a recorded tolerance is `2.0` x contact distance / closing speed.
    assert_eq!(nearmiss_cli::regression::RECORD_TOLERANCE_FACTOR, 2.0);
}
