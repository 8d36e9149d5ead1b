//! Han's questions, the failure questions and "Can you X?", asked in the
//! user's words: answered by `explain` about the node picked or running.

use super::compose::Context;
use super::Reply;
use crate::explain::Question;

pub fn answer(cx: &Context, q: &Question, r: &mut Reply) -> Result<(), String> {
    let uid = match (cx.node, cx.at.as_ref()) {
        (Some(u), _) => u,
        (None, Some(at)) => at.current().ok_or_else(|| {
            format!(
                "nothing has been ticked yet at moment {}; pick a node with --node",
                at.moment()
            )
        })?,
        (None, None) => {
            return Err(
                "pick the node to ask about with --node (a tree has no current node)".into(),
            )
        }
    };
    let a = crate::explain::answer(cx.tree, cx.at.as_ref(), uid, q)?;
    r.about = Some(uid);
    r.understood = q.wording();
    r.answer = a.text;
    r.nodes = a.nodes;
    r.insertion = a.insertion;
    Ok(())
}
