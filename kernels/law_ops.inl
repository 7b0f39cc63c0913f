// The operations a law uses on Vec3T<R> and QuatT<R> (part of kernels/laws.inl; no include guard on purpose).

template <class R>
VITRUM_LAW Vec3T<R> operator+(const Vec3T<R>& a, const Vec3T<R>& b) noexcept {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class R>
VITRUM_LAW Vec3T<R> operator-(const Vec3T<R>& a, const Vec3T<R>& b) noexcept {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class R>
VITRUM_LAW Vec3T<R> operator-(const Vec3T<R>& a) noexcept {
    return {-a.x, -a.y, -a.z};
}
/// s a, with s a number of R or a double constant.
template <class S, class R>
VITRUM_LAW Vec3T<R> operator*(const S& s, const Vec3T<R>& a) noexcept {
    return {s * a.x, s * a.y, s * a.z};
}
template <class R>
VITRUM_LAW R dot(const Vec3T<R>& a, const Vec3T<R>& b) noexcept {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class R>
VITRUM_LAW Vec3T<R> cross(const Vec3T<R>& a, const Vec3T<R>& b) noexcept {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class R>
VITRUM_LAW QuatT<R> conjugate(const QuatT<R>& q) noexcept {
    return {q.w, -q.x, -q.y, -q.z};
}
/// Hamilton product a b.
template <class R>
VITRUM_LAW QuatT<R> operator*(const QuatT<R>& a, const QuatT<R>& b) noexcept {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y + a.y * b.w + a.z * b.x - a.x * b.z, a.w * b.z + a.z * b.w + a.x * b.y - a.y * b.x};
}
/// q v q* for a unit q: t = 2 q.vec × v; v + w t + q.vec × t.
template <class R>
VITRUM_LAW Vec3T<R> rotate(const QuatT<R>& q, const Vec3T<R>& v) noexcept {
    const Vec3T<R> u{q.x, q.y, q.z};
    const Vec3T<R> t = 2.0 * cross(u, v);
    return v + q.w * t + cross(u, t);
}

/// √x, lane by lane for a lane vector.
template <class R>
VITRUM_LAW R sqrtOf(R x) noexcept {
    if constexpr (std::is_floating_point_v<R>) {
        return std::sqrt(x);
    } else {
        R r;
        for (int l = 0; l < static_cast<int>(sizeof(R) / sizeof(double)); ++l) {
            r[l] = std::sqrt(x[l]);
        }
        return r;
    }
}
