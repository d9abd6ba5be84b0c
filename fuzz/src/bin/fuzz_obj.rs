//! AFL target: [`tessgen_fuzz::obj`].
fn main() {
    afl::fuzz!(|data: &[u8]| {
        tessgen_fuzz::obj(data);
    });
}
