// RBF kernels (thesis, eqs. 9-10) and the neighbourhood both rbf_solve and interpolate use:
// a point q and the first k-1 of its stored neighbours that point_sample sampled.
#ifndef RBF_GLSL
#define RBF_GLSL

float rbfKernel(float r, float c, uint kernel) {
    if (kernel == kKernelGaussian) {
        float x = r / c;
        return exp(-x * x);
    }
    return sqrt(r * r + c * c);
}

bool isSampled(vec2 canvasPos, vec2 offset, vec2 size, float margin) {
    vec2 s = canvasPos + offset;
    return all(greaterThanEqual(s, vec2(-margin))) && all(lessThan(s, size + margin));
}
#endif
