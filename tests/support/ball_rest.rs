//! The shipped `ball_rest` scene under `Bounce(restitution: 0.5)`, without
//! its expectation (a Simulate contact time): a ball that bounces lower and
//! lower and then lies on the floor, with hundreds of contacts.

/// The scene's RON text.
pub fn under_bounce() -> String {
    // Relative to this file: the library's tests and the application's
    // (`cli/tests/outputs/plots.rs`) share it.
    let text = include_str!("../../scenes/ball_rest.ron")
        .replace("Simulate(restitution: 0.5)", "Bounce(restitution: 0.5)");
    text[..text.find("    expect:").unwrap()].to_string() + ")"
}
