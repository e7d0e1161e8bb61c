// Clip colours in the order clips are given (the first is typically the reconstruction). Also read
// by the page test (test/view_page_test.mjs) to find each clip in a screenshot.
export const CLIP_COLOURS = ['#ff8a1f', '#2f9bff', '#3ddc52', '#e84ef0', '#ffe03a', '#26d9d0'];
