//! AFL target: [`tessgen_fuzz::tags`].
fn main() {
    afl::fuzz!(|data: &[u8]| {
        tessgen_fuzz::tags(data);
    });
}
