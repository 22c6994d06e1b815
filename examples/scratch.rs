fn main() {
    let p = std::env::args().nth(1).unwrap();
    match traxer::mesh::load(std::path::Path::new(&p)) {
        Ok((m, r)) => println!("{} tris {} verts max idx {:?} warnings {:?}", m.triangles.len(), m.positions.len(), m.triangles.iter().flatten().max(), r.warnings),
        Err(e) => println!("ERR {e}"),
    }
}
