//! `micromap-lab prove --all-levels`: exit 0 when the product search
//! proves the walk for every level, 1 with a confirmed face for version 1,
//! 2 on a usage error.

#[path = "../../cli/tests/common/mod.rs"]
mod cli;

fn command(args: &[&str]) -> std::process::Output {
    cli::run(args)
}

#[test]
fn command_exits_0_when_proved_and_1_for_version1() {
    let proved = command(&["prove", "--all-levels"]);
    let text = String::from_utf8_lossy(&proved.stdout);
    assert_eq!(proved.status.code(), Some(0), "{text}");
    assert!(text.contains("proved in"), "{text}");

    let refuted = command(&["prove", "--all-levels", "--version1"]);
    let text = String::from_utf8_lossy(&refuted.stdout);
    assert_eq!(refuted.status.code(), Some(1), "{text}");
    assert!(text.contains("confirmed by the real functions"), "{text}");

    let json = command(&["prove", "--all-levels", "--version1", "--json"]);
    let text = String::from_utf8_lossy(&json.stdout);
    assert_eq!(json.status.code(), Some(1), "{text}");
    assert!(text.contains("\"verdict\":\"counterexample\""), "{text}");
    assert!(text.contains("\"confirmed\":true"), "{text}");

    let bad = command(&["prove", "--all-levels", "--levels", "3"]);
    assert_eq!(bad.status.code(), Some(2));
}
