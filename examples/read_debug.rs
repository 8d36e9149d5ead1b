fn main() {
    let args: Vec<String> = std::env::args().collect();
    let input = btx::input::open(std::path::Path::new(&args[1]), &Default::default()).unwrap();
    let tree = input.tree();
    let v = btx::ask::read::Vocabulary::new(tree);
    for q in &args[2..] {
        let words = btx::ask::read::words::words(q);
        println!(
            "{:?}",
            words
                .iter()
                .map(|w| format!("{}/{}", w.text, w.stem))
                .collect::<Vec<_>>()
        );
        println!("{:?}", v.mentions(tree, &words, &|_| false));
        println!("{:?}", btx::ask::read::read(&v, tree, q));
    }
}
