//! A bag's MCAP file rewritten in small chunks by the `mcap` crate's own
//! writer, as a recorder with a small chunk size writes it up to its
//! summary (which a recorder killed never writes). Shared by the bag
//! reader's unit tests (`src/logs/rosbag`) and `tests/rosbag.rs`.

use std::path::Path;

/// `mcap_file` rewritten into `out` in chunks of about `size` bytes, with
/// its indexes and statistics where `indexes`, else its messages alone.
pub fn rechunked(mcap_file: &Path, size: u64, indexes: bool, out: &Path) {
    let bytes = std::fs::read(mcap_file).unwrap();
    let mut w = mcap::WriteOptions::new()
        .chunk_size(Some(size))
        .emit_message_indexes(indexes)
        .emit_summary_records(false)
        .emit_summary_offsets(false)
        .emit_chunk_indexes(indexes)
        .emit_statistics(indexes)
        .create(std::io::BufWriter::new(std::fs::File::create(out).unwrap()))
        .unwrap();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        w.write(&m.unwrap()).unwrap();
    }
    w.finish().unwrap();
}
