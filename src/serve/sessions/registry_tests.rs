//! The registry's unit test: `sessions.json` with an entry in every state and a verification of
//! every status, read and written back byte for byte.

use super::*;

    /// A `sessions.json` as docs/serve.md describes it, written out by hand: one entry in every
    /// state, and a verification of every status.
    const LISTED: &str = r#"{
  "format": "grove-sessions",
  "version": 1,
  "sessions": [
    {
      "id": "00000000000000000000000000000001",
      "file": "P01-manual-7-1.jsonl",
      "participant": "P01",
      "task": "manual-7",
      "opened": "2026-12-01T09:01:12Z",
      "state": "open",
      "lines": 701
    },
    {
      "id": "00000000000000000000000000000002",
      "file": "P02-ray-casting-7-1.jsonl",
      "participant": "P02",
      "task": "ray-casting-7",
      "opened": "2026-12-01T09:01:13Z",
      "state": "ended",
      "lines": 4113,
      "closed": "2026-12-01T09:02:40Z",
      "verification": {
        "status": "verified",
        "complete": true,
        "checkpoints_checked": 89,
        "verified_to_tick": 5285,
        "last_tick": 5285,
        "first_divergence": null,
        "error": null
      }
    },
    {
      "id": "00000000000000000000000000000003",
      "file": "P03-free-1.jsonl",
      "participant": "P03",
      "task": null,
      "opened": "2026-12-01T09:03:00Z",
      "state": "abandoned",
      "lines": 12,
      "closed": "2026-12-01T09:13:00Z",
      "verification": {
        "status": "incomplete",
        "complete": false,
        "checkpoints_checked": 0,
        "verified_to_tick": 0,
        "last_tick": 40,
        "first_divergence": null,
        "error": null
      }
    },
    {
      "id": "00000000000000000000000000000004",
      "file": "P04-manual-7-1.jsonl",
      "participant": "P04",
      "task": "manual-7",
      "opened": "2026-12-01T09:04:00Z",
      "state": "ended",
      "lines": 300,
      "closed": "2026-12-01T09:05:00Z",
      "verification": {
        "status": "unverified",
        "complete": true,
        "checkpoints_checked": 0,
        "verified_to_tick": 120,
        "last_tick": 120,
        "first_divergence": null,
        "error": null
      }
    },
    {
      "id": "00000000000000000000000000000005",
      "file": "P05-manual-7-1.jsonl",
      "participant": "P05",
      "task": "manual-7",
      "opened": "2026-12-01T09:05:00Z",
      "state": "ended",
      "lines": 900,
      "closed": "2026-12-01T09:06:00Z",
      "verification": {
        "status": "diverged",
        "complete": true,
        "checkpoints_checked": 3,
        "verified_to_tick": null,
        "last_tick": 600,
        "first_divergence": {
          "tick": 180,
          "expected_hash": "0123456789abcdef",
          "actual_hash": "fedcba9876543210"
        },
        "error": null
      }
    },
    {
      "id": "00000000000000000000000000000006",
      "file": "P06-manual-7-1.jsonl",
      "participant": "P06",
      "task": "manual-7",
      "opened": "2026-12-01T09:06:00Z",
      "state": "abandoned",
      "lines": 2,
      "closed": "2026-12-01T09:16:00Z",
      "verification": {
        "status": "invalid",
        "complete": false,
        "checkpoints_checked": 0,
        "verified_to_tick": null,
        "last_tick": 0,
        "first_divergence": null,
        "error": "line 2: bad checksum"
      }
    },
    {
      "id": "00000000000000000000000000000007",
      "file": "P07-manual-7-1.jsonl",
      "participant": "P07",
      "task": "manual-7",
      "opened": "2026-12-01T09:07:00Z",
      "state": "unresumable",
      "lines": 5,
      "note": "P07-manual-7-1.jsonl:6: the line's checksum does not match"
    }
  ]
}
"#;

    #[test]
    fn sessions_json_in_every_state_is_read_and_written_back_byte_for_byte() {
        let dir = tempfile::tempdir().unwrap();
        let study = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("replays/study/P01-manual-7.jsonl");
        std::fs::copy(study, dir.path().join("P01-manual-7-1.jsonl")).unwrap();
        std::fs::write(dir.path().join(SESSIONS_FILE), LISTED).unwrap();
        let (registry, notes) = Registry::load(dir.path(), Vec::new(), 4).unwrap();
        assert_eq!(notes, ["continuing P01-manual-7-1.jsonl (701 lines)"]);
        let states: Vec<SessionState> = registry.entries().iter().map(|e| e.state).collect();
        use SessionState::*;
        assert_eq!(states, [Open, Ended, Abandoned, Ended, Ended, Abandoned, Unresumable]);
        registry.save().unwrap();
        assert_eq!(std::fs::read_to_string(dir.path().join(SESSIONS_FILE)).unwrap(), LISTED);
    }
