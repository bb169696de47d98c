use kernel_gen::physics::fd::*;

#[test]
fn stencils_are_the_textbook_ones() {
    assert_eq!(stencil(1), vec![(-1, -0.5), (1, 0.5)]);
    assert_eq!(stencil(2), vec![(-1, 1.0), (0, -2.0), (1, 1.0)]);
    assert_eq!(
        stencil(4),
        vec![(-2, 1.0), (-1, -4.0), (0, 6.0), (1, -4.0), (2, 1.0)]
    );
    assert_eq!(stencil(3), vec![(-2, -0.5), (-1, 1.0), (1, -1.0), (2, 0.5)]);
}
