//! Every client text is parsed into the typed enum or refused with a reason.

use usar_console::protocol::{ClientMessage, DriveCommand, ProtocolError, parse};

#[test]
fn valid_messages_parse_into_their_variants() {
    assert_eq!(parse(r#"{"type":"pause"}"#), Ok(ClientMessage::Pause {}));
    assert_eq!(
        parse(r#"{"type":"drive","robot":0,"command":"left"}"#),
        Ok(ClientMessage::Drive {
            robot: 0,
            command: DriveCommand::Left
        })
    );
    assert_eq!(
        parse(r#"{"type":"answer_victim","handoff":3,"tag":true}"#),
        Ok(ClientMessage::AnswerVictim {
            handoff: 3,
            tag: true
        })
    );
    assert!(parse(r#"{"type":"weights","w_l":1,"w_p":2.5,"w_q":0}"#).is_ok());
    assert!(parse(r#"{"type":"hypothesis","name":"small"}"#).is_ok());
}

#[test]
fn malformed_and_out_of_range_messages_are_refused_with_a_reason() {
    for bad in [
        "",
        "not json",
        "{}",
        "[]",
        r#"{"type":"launch_rockets"}"#,
        r#"{"type":"pause","extra":1}"#,
        r#"{"type":"drive","robot":0}"#,
        r#"{"type":"drive","robot":-1,"command":"left"}"#,
        r#"{"type":"drive","robot":0,"command":"jump"}"#,
        r#"{"type":"speed","factor":0}"#,
        r#"{"type":"speed","factor":1e9}"#,
        r#"{"type":"speed","factor":"fast"}"#,
        r#"{"type":"weights","w_l":-1,"w_p":1,"w_q":1}"#,
        r#"{"type":"hypothesis","name":"everywhere"}"#,
        r#"{"type":"answer_victim","handoff":1}"#,
    ] {
        let e = parse(bad).expect_err(bad);
        assert!(!e.to_string().is_empty(), "{bad}: an empty reason");
    }
    let long = format!(r#"{{"type":"auth","token":"{}"}}"#, "x".repeat(5000));
    assert_eq!(parse(&long), Err(ProtocolError::TooLong(long.len())));
    assert!(parse(&long).unwrap_err().to_string().contains("4096"));
    assert_eq!(
        parse(r#"{"type":"speed","factor":0}"#),
        Err(ProtocolError::OutOfRange {
            field: "speed factor",
            found: "0".into(),
            expected: "0 < factor ≤ 1000"
        })
    );
}
