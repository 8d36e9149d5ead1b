//! A Groot2 server that floods, for `benches/flood.sh`:
//!
//!   flood_peer SESSION RECORDS_PER_REPLY BUFFER SECONDS
//!
//! prints its port, then answers for SECONDS.

#[path = "../tests/support/flood_peer.rs"]
mod flood_peer;

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let [run, records, buffer, secs] = &a[..] else {
        eprintln!("usage: flood_peer SESSION RECORDS_PER_REPLY BUFFER SECONDS");
        std::process::exit(2);
    };
    let num = |s: &str| s.parse::<u64>().expect("a number");
    let (port, stop) = flood_peer::flooding(
        std::path::Path::new(run),
        num(records),
        num(buffer) as usize,
    );
    println!("{port}");
    std::thread::sleep(std::time::Duration::from_secs(num(secs)));
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
}
