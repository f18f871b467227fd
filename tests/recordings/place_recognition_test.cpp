#include "recordings/place_recognition.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

// Descriptors that are exactly the unit vectors of the listed words (4-D, one word per axis).
Eigen::MatrixXf Words(const std::vector<int>& words) {
  Eigen::MatrixXf d = Eigen::MatrixXf::Zero(static_cast<Eigen::Index>(words.size()), 4);
  for (std::size_t i = 0; i < words.size(); ++i) d(static_cast<Eigen::Index>(i), words[i]) = 1.0f;
  return d;
}

Vocabulary Axes() { return Vocabulary(Eigen::MatrixXf::Identity(4, 4)); }

TEST(PlaceRecognition, QuantizeGivesTheNearestWord) {
  Eigen::MatrixXf d(3, 4);
  d << 0.9f, 0.1f, 0, 0,    //
      0, 0.2f, 0.1f, 0.8f,  //
      0, 0.6f, 0.5f, 0;
  EXPECT_EQ(Axes().Quantize(d), (std::vector<int>{0, 3, 1}));
  // Equally near two words: the lower index.
  Eigen::MatrixXf tie(1, 4);
  tie << 0, 0, 0.5f, 0.5f;
  EXPECT_EQ(Axes().Quantize(tie), (std::vector<int>{2}));
}

TEST(PlaceRecognition, TfIdfCosineIsExact) {
  // Keyframe 0 holds words {0, 0, 1}, keyframe 1 {0, 1, 2}, keyframe 2 {3}. N = 3; words 0 and 1
  // are in two keyframes (idf log 1.5), words 2 and 3 in one (idf log 3).
  PlaceIndex index(Axes());
  EXPECT_EQ(index.Add(Words({0, 0, 1})), 0);
  EXPECT_EQ(index.Add(Words({0, 1, 2})), 1);
  EXPECT_EQ(index.Add(Words({3})), 2);
  index.Finalize();
  const double l = std::log(1.5), L = std::log(3.0);
  EXPECT_NEAR(index.Idf(0), l, 1e-12);
  EXPECT_NEAR(index.Idf(2), L, 1e-12);
  // Keyframe 0's weights: (2/3 l, 1/3 l) ~ (2, 1) / sqrt(5); keyframe 1's: (l, l, L) / norm.
  const double expected = (2 * l + l) / (std::sqrt(5.0) * std::sqrt(2 * l * l + L * L));
  EXPECT_NEAR(index.Similarity(0, 1), expected, 1e-6);
  EXPECT_NEAR(index.Similarity(1, 0), expected, 1e-6);
  EXPECT_NEAR(index.Similarity(0, 0), 1.0, 1e-6);
  EXPECT_EQ(index.Similarity(0, 2), 0.0);

  const std::vector<PlaceCandidate> ranked = index.Rank(1, {0, 1, 2}, 5);
  ASSERT_EQ(ranked.size(), 2u);  // the query itself is skipped
  EXPECT_EQ(ranked[0].id, 0);
  EXPECT_EQ(ranked[1].id, 2);
  EXPECT_EQ(index.Rank(1, {0, 2}, 1).size(), 1u);
}

TEST(PlaceRecognition, AWordInEveryKeyframeWeighsNothing) {
  // Word 0 is everywhere (idf 0): the keyframes that share only it are not similar at all, and
  // rare shared words decide the ranking.
  PlaceIndex index(Axes());
  index.Add(Words({0, 0, 0, 1}));
  index.Add(Words({0, 2}));
  index.Add(Words({0, 1, 3}));
  index.Add(Words({0, 0, 0, 0, 3}));
  index.Finalize();
  EXPECT_EQ(index.Idf(0), 0.0);
  EXPECT_EQ(index.Similarity(0, 1), 0.0);
  EXPECT_EQ(index.Similarity(3, 1), 0.0);
  const std::vector<PlaceCandidate> ranked = index.Rank(0, {1, 2, 3}, 3);
  EXPECT_EQ(ranked[0].id, 2);  // shares word 1
  // Keyframes 1 and 3 share nothing weighted with 0: equal scores, in id order.
  EXPECT_EQ(ranked[1].id, 1);
  EXPECT_EQ(ranked[2].id, 3);
  EXPECT_EQ(ranked[1].score, 0.0);
}

// Three tight clusters about the first three axes of an 8-D space; cluster c of size n.
Eigen::MatrixXf Cluster(int c, int n, float spread) {
  Eigen::MatrixXf d = Eigen::MatrixXf::Zero(n, 8);
  for (int i = 0; i < n; ++i) {
    d(i, c) = 1.0f;
    d(i, 3 + i % 5) = spread * static_cast<float>(i % 3 - 1);  // deterministic jitter
  }
  return d;
}

TEST(PlaceRecognition, KMeansFindsSeparatedClustersDeterministically) {
  const std::vector<Eigen::MatrixXf> sets = {Cluster(0, 30, 0.05f), Cluster(1, 20, 0.05f),
                                             Cluster(2, 25, 0.05f)};
  VocabularyConfig config;
  config.words = 3;
  const Vocabulary v = Vocabulary::Train(sets, config);
  ASSERT_EQ(v.size(), 3);
  // Each cluster maps to one word of its own.
  std::vector<int> word_of(3);
  for (int c = 0; c < 3; ++c) {
    const std::vector<int> q = v.Quantize(sets[static_cast<std::size_t>(c)]);
    word_of[static_cast<std::size_t>(c)] = q[0];
    for (int w : q) EXPECT_EQ(w, q[0]) << "cluster " << c;
  }
  EXPECT_NE(word_of[0], word_of[1]);
  EXPECT_NE(word_of[1], word_of[2]);
  EXPECT_NE(word_of[0], word_of[2]);
  // A centre is its cluster's mean: the axis at 1, the symmetric jitter averaging near 0.
  EXPECT_NEAR(v.centers()(word_of[1], 1), 1.0f, 1e-6f);
  // Same input and seed, same words.
  EXPECT_EQ(Vocabulary::Train(sets, config).centers(), v.centers());
  // Fewer distinct descriptors than words: one word each.
  config.words = 10;
  EXPECT_EQ(Vocabulary::Train({Words({0, 1, 1, 2})}, config).size(), 3);
}

TEST(PlaceRecognition, FarApartCandidatesSkipNeighboursAndUnrelatedKeyframes) {
  // Keyframes 0, 1 and 3 show words 1 and 2; keyframe 2 shows others. At least two apart: 0 asks
  // about 2 and 3 (3 is the same words), 1 about 3, 2 about 0 (nothing shared: no pair), 3 about
  // 0 and 1 (0 is the better; the pair is already there).
  PlaceIndex index(Axes());
  index.Add(Words({1, 1, 2}));
  index.Add(Words({1, 2}));
  index.Add(Words({0, 3}));
  index.Add(Words({1, 1, 2}));
  index.Finalize();
  EXPECT_EQ(FarApartCandidates(index, 2, 1), (std::vector<std::pair<int, int>>{{0, 3}, {1, 3}}));
  EXPECT_TRUE(FarApartCandidates(index, 4, 5).empty());
}

TEST(PlaceRecognition, MutualMatchesCountOneToOnePairsAboveTheCosine) {
  // a's rows: axes 0, 1, 2 and a second row near axis 0; b's rows: axes 0, 1 and 3. Axis 0 of b
  // is the nearest of both a-rows 0 and 3, but only row 0 is its nearest back: mutual pairs are
  // (0, 0) and (1, 1); a's axis 2 has no partner above the cosine.
  Eigen::MatrixXf a = Words({0, 1, 2, 0});
  a.row(3) << 0.8f, 0.6f, 0, 0;
  const Eigen::MatrixXf b = Words({0, 1, 3});
  EXPECT_EQ(MutualMatches(a, b, 0.5f), 2);
  EXPECT_EQ(MutualMatches(b, a, 0.5f), 2);
  EXPECT_EQ(MutualMatches(a, b, 0.5f, 1), 1);  // only the first row of each
  EXPECT_EQ(MutualMatches(a, Eigen::MatrixXf(0, 4)), 0);
  EXPECT_THROW(MutualMatches(a, Eigen::MatrixXf::Zero(2, 5)), InputError);

  // Re-ranking: keyframe 2 shares two matches with the query 0, keyframe 1 one.
  const std::vector<Eigen::MatrixXf> d = {Words({0, 1, 2}), Words({2, 3}), Words({0, 1})};
  const auto out = RerankByMatches({{1, 0.9}, {2, 0.5}}, 0, d, 0.5f);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].id, 2);
  EXPECT_EQ(out[0].score, 2.0);
  EXPECT_EQ(out[1].id, 1);
  EXPECT_EQ(out[1].score, 1.0);
}

// Each keyframe with its neighbours in its own recording, never across into the other one.
TEST(PlaceRecognition, NeighboursJoinWithinTheirRecordingOnly) {
  const std::vector<Eigen::MatrixXf> sets = {Words({0}), Words({1}), Words({2}), Words({3}),
                                             Words({0, 3})};
  const std::vector<Eigen::MatrixXf> same = WithNeighbours(sets, {3, 2}, 0);
  ASSERT_EQ(same.size(), sets.size());
  for (std::size_t i = 0; i < sets.size(); ++i) EXPECT_TRUE(same[i].isApprox(sets[i]));
  const std::vector<Eigen::MatrixXf> joined = WithNeighbours(sets, {3, 2}, 1);
  ASSERT_EQ(joined.size(), sets.size());
  const std::vector<Eigen::Index> rows = {2, 3, 2, 3,
                                          3};  // keyframe 2 stops at its recording's end
  for (std::size_t i = 0; i < sets.size(); ++i) EXPECT_EQ(joined[i].rows(), rows[i]) << i;
  EXPECT_TRUE(joined[2].isApprox((Eigen::MatrixXf(2, 4) << sets[1], sets[2]).finished()));
  EXPECT_TRUE(joined[3].isApprox((Eigen::MatrixXf(3, 4) << sets[3], sets[4]).finished()));
  EXPECT_THROW(WithNeighbours(sets, {3, 1}, 1), InputError);
  EXPECT_THROW(WithNeighbours(sets, {3, 2}, -1), InputError);
}

TEST(PlaceRecognition, BadInputIsRefused) {
  EXPECT_THROW(Vocabulary::Train({}), InputError);
  EXPECT_THROW(Vocabulary::Train({Eigen::MatrixXf(2, 4), Eigen::MatrixXf(2, 5)}), InputError);
  VocabularyConfig config;
  config.words = 0;
  EXPECT_THROW(Vocabulary::Train({Words({0})}, config), InputError);
  PlaceIndex index(Axes());
  EXPECT_THROW(index.Add(Eigen::MatrixXf::Zero(2, 5)), InputError);
  index.Add(Words({0}));
  EXPECT_THROW(index.Similarity(0, 0), std::logic_error);  // before Finalize
  index.Finalize();
  EXPECT_THROW(index.Similarity(0, 1), InputError);
}

}  // namespace
}  // namespace zeroreg
