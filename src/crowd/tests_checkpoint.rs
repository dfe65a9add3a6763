//! Crowd checkpoints: a crowd resumed from its checkpoint goes on bit for bit, and a checkpoint
//! is refused by any other world (a lone character, a crowd placed elsewhere).

use super::tests::shot;
use super::*;
use crate::pipeline::{Checkpoint, Pipeline, PipelineError, PipelineState};

const CHARACTERS: &str = "[[character]]\nposition = [0.0, 0.0, 0.0]\nmotion = { kind = \"shake\" }\n\
     [[character]]\nposition = [0.4, 0.0, -0.3]\nwind = { speed = 3.0, gusts = 2.0 }\n\
     [[character]]\nposition = [-0.4, 0.0, -0.6]\nmotion = { kind = \"nod\" }\n";

fn states(crowd: &Crowd) -> Vec<PipelineState> {
    crowd.checkpoint().unwrap().states().cloned().collect()
}

#[test]
fn a_crowd_resumed_from_its_checkpoint_goes_on_bit_for_bit() {
    let shot = shot(CHARACTERS);
    let model = CrowdModel::build(&shot).unwrap();
    let mut straight = Crowd::new(&model, shot.settings).unwrap();
    let mut first = Crowd::new(&model, shot.settings).unwrap();
    for frame in 0..4 {
        straight.advance(&shot.camera(frame)).unwrap();
        first.advance(&shot.camera(frame)).unwrap();
    }
    let dir = std::env::temp_dir().join(format!("hairlod-crowd-ckpt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("checkpoint.json");
    let checkpoint = first.checkpoint().unwrap();
    assert_eq!(checkpoint.others.len(), 2, "one state per character");
    checkpoint.write(&path).unwrap();
    let read = Checkpoint::read(&path).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(read, checkpoint);
    let mut resumed = Crowd::resume(&model, shot.settings, read).unwrap();
    assert_eq!(resumed.frame(), 4);
    for frame in 4..8 {
        let a = straight.advance(&shot.camera(frame)).unwrap();
        let b = resumed.advance(&shot.camera(frame)).unwrap();
        assert_eq!(a.sections_at, b.sections_at, "frame {frame}");
    }
    let (a, b) = (states(&straight), states(&resumed));
    assert!(a == b, "the resumed crowd differs from the straight run");
    // The characters moved differently, so the comparison covers each one's own state.
    assert!(a[0].blocks != a[1].blocks);
}

#[test]
fn a_crowd_checkpoint_resumes_only_its_own_crowd() {
    let shot = shot(CHARACTERS);
    let model = CrowdModel::build(&shot).unwrap();
    let mut crowd = Crowd::new(&model, shot.settings).unwrap();
    crowd.advance(&shot.camera(0)).unwrap();
    let checkpoint = crowd.checkpoint().unwrap();
    // The same characters, the last one placed elsewhere.
    let moved = super::tests::shot(&CHARACTERS.replace("[-0.4, 0.0, -0.6]", "[-0.5, 0.0, -0.6]"));
    let other = CrowdModel::build(&moved).unwrap();
    let refused = Crowd::resume(&other, moved.settings, checkpoint.clone());
    assert!(
        matches!(refused, Err(PipelineError::ForeignCheckpoint { .. })),
        "another crowd resumed"
    );
    // A lone character of the first groom and place does not take the crowd's checkpoint.
    let member = &model.members[0];
    let alone = Pipeline::resume(
        (*member.scene).clone(),
        member.character.environment.clone(),
        shot.settings,
        checkpoint,
    );
    assert!(matches!(
        alone,
        Err(PipelineError::ForeignCheckpoint { .. })
    ));
}
