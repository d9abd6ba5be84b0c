//! AFL target: [`tessgen_fuzz::mesh`].
fn main() {
    afl::fuzz!(|data: &[u8]| {
        tessgen_fuzz::mesh(data);
    });
}
